// printwatt view: the page's script. Talks to the server under /api/ (docs/view.md).
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/OrbitControls.js';
import { STLLoader } from 'three/addons/loaders/STLLoader.js';
import { ColladaLoader } from 'three/addons/loaders/ColladaLoader.js';
import { OBJLoader } from 'three/addons/loaders/OBJLoader.js';

const token = new URLSearchParams(location.search).get('token') || '';
const api = (p) => p + (token ? '?token=' + encodeURIComponent(token) : '');
const $ = (id) => document.getElementById(id);
const fmt = (v, d) => (v === null || v === undefined || !isFinite(v)) ? 'n/a' : Number(v).toFixed(d);

// The scene is drawn when something may have changed (an answer from the server, an input, a
// camera move, playback), never in an idle loop: an idle view costs no processor time.
let drawQueued = false;
function requestDraw() {
  if (!drawQueued) { drawQueued = true; requestAnimationFrame(draw); }
}
async function getJSON(path) {
  const r = await fetch(api(path));
  const v = await r.json();
  requestDraw();
  return v;
}
async function postJSON(path, body) {
  const r = await fetch(api(path), { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body) });
  const v = await r.json();
  if (!r.ok && !v.error) v.error = 'HTTP ' + r.status;
  requestDraw();
  return v;
}

// State shared with tests (window.pwView).
const view = { scene: null, place: { x_m: 0, y_m: 0, z_m: 0, yaw_deg: 0, spin_deg: 0 }, seq: 0, applied: 0, last: null, playback: null, ready: false };
window.pwView = view;

THREE.Object3D.DEFAULT_UP.set(0, 0, 1);
const host = $('scene');
const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio || 1);
renderer.setClearColor(0xeef1f4);
host.appendChild(renderer.domElement);
const scene3 = new THREE.Scene();
const camera = new THREE.PerspectiveCamera(45, 1, 0.01, 100);
const controls = new OrbitControls(camera, renderer.domElement);
controls.addEventListener('change', requestDraw);
for (const ev of ['input', 'change', 'click', 'keyup', 'pointermove', 'pointerup', 'wheel']) {
  document.addEventListener(ev, requestDraw, { passive: true });
}
scene3.add(new THREE.HemisphereLight(0xffffff, 0x667788, 2.0));
const sun = new THREE.DirectionalLight(0xffffff, 1.5);
sun.position.set(3, -4, 6);
scene3.add(sun);

function resize() {
  const w = host.clientWidth || 800, h = host.clientHeight || 600;
  renderer.setSize(w, h, false);
  camera.aspect = w / h;
  camera.updateProjectionMatrix();
  requestDraw();
}
window.addEventListener('resize', resize);

// ---- robot: the URDF's visual geometry where a link has it, else its collision shapes ----
// One group per collision shape (posed from the server's shape poses) and one per body
// (0 the fixed base, i the link of joint i; posed from the server's body frames) holding
// that body's visual elements at their URDF origins.
const robot = new THREE.Group();
scene3.add(robot);
const shapeObjs = [];
const bodyObjs = [];
const visualObjs = [];
const colours = { link: 0xe07b24, head: 0x8a8f98, hose: 0x333333 };
const visualMat = new THREE.MeshStandardMaterial({ color: 0xe8a33d, roughness: 0.55, metalness: 0.15 });
// What the robot is drawn from (for the page's line and for tests).
view.drawn = { visual: 0, collision: 0, failed: [], visualBodies: [] };

function shapeMesh(s) {
  const mat = new THREE.MeshStandardMaterial({ color: colours[s.role] || 0xe07b24, roughness: 0.6, metalness: 0.1 });
  const g = new THREE.Group();
  if (s.kind === 'capsule') {
    const a = new THREE.Vector3(...s.a_m), b = new THREE.Vector3(...s.b_m);
    const d = b.clone().sub(a);
    const m = new THREE.Mesh(new THREE.CapsuleGeometry(s.radius_m, Math.max(d.length(), 1e-4), 4, 16), mat);
    m.position.copy(a.clone().add(b).multiplyScalar(0.5));
    if (d.length() > 1e-9) m.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), d.normalize());
    g.add(m);
  } else if (s.kind === 'box') {
    g.add(new THREE.Mesh(new THREE.BoxGeometry(2 * s.half_m[0], 2 * s.half_m[1], 2 * s.half_m[2]), mat));
  } else if (s.kind === 'cylinder') {
    g.add(new THREE.Mesh(new THREE.CylinderGeometry(s.radius_m, s.radius_m, 2 * s.half_height_m, 20), mat));
  } else if (s.kind === 'hull') {
    // A convex piece of a link (a link may have several): its own triangles, to scale.
    const geo = new THREE.BufferGeometry();
    geo.setAttribute('position', new THREE.Float32BufferAttribute(s.vertices_m.flat(), 3));
    geo.setIndex(s.triangles.flat());
    geo.computeVertexNormals();
    const m = new THREE.Mesh(geo, mat);
    m.userData.hull = true;
    g.add(m);
  } else {
    const m = new THREE.Mesh(new THREE.SphereGeometry(s.radius_m, 16, 12), mat);
    m.position.set(...s.centre_m);
    g.add(m);
  }
  return g;
}

// A visual mesh file's object in its file's frame and units, turned into the link frame's
// metres: STL and OBJ as they are; COLLADA scaled by its <unit meter> (the loader does that)
// with its <up_axis> taken as the link's z (the loader turns Z_UP files to three.js's Y up,
// undone here; Y_UP and X_UP files are turned so that their up axis is z).
function meshObject(format, data) {
  if (format === 'stl') {
    const geo = new STLLoader().parse(data);
    geo.computeVertexNormals();
    return new THREE.Mesh(geo, visualMat);
  }
  if (format === 'obj') {
    const g = new OBJLoader().parse(new TextDecoder().decode(data));
    g.traverse((m) => { if (m.isMesh) m.material = visualMat; });
    return g;
  }
  const text = new TextDecoder().decode(data);
  // No texture is fetched: the server serves meshes only.
  const manager = new THREE.LoadingManager();
  manager.setURLModifier(() => 'data:,');
  const dae = new ColladaLoader(manager).parse(text, '');
  if (!dae || !dae.scene) throw new Error('not a COLLADA file');
  const up = (text.match(/<up_axis>\s*([XYZ]_UP)\s*<\/up_axis>/) || [null, 'Y_UP'])[1];
  const sc = dae.scene;
  sc.rotation.set(0, 0, 0);
  if (up === 'Y_UP') sc.rotation.set(Math.PI / 2, 0, 0);
  if (up === 'X_UP') sc.rotation.set(0, -Math.PI / 2, 0);
  let meshes = 0;
  sc.traverse((m) => { if (m.isMesh) { m.material = visualMat; meshes++; } });
  if (!meshes) throw new Error('no geometry in the COLLADA file');
  return sc;
}

const meshCache = new Map();
function loadMesh(k, format) {
  if (!meshCache.has(k)) {
    meshCache.set(k, fetch(api('/api/mesh/' + k)).then(async (r) => {
      if (!r.ok) throw new Error('HTTP ' + r.status);
      return meshObject(format, await r.arrayBuffer());
    }));
  }
  return meshCache.get(k).then((o) => o.clone());
}

function visualPrimitive(v) {
  if (v.kind === 'box') return new THREE.Mesh(new THREE.BoxGeometry(...v.size_m), visualMat);
  if (v.kind === 'sphere') return new THREE.Mesh(new THREE.SphereGeometry(v.radius_m, 24, 16), visualMat);
  // URDF cylinders run along z, three.js's along y.
  const m = new THREE.Mesh(new THREE.CylinderGeometry(v.radius_m, v.radius_m, v.length_m, 24), visualMat);
  m.rotation.set(Math.PI / 2, 0, 0);
  return m;
}

// Build every visual element; a body whose elements all load is drawn from them and its
// collision shapes are hidden; a body with an element that fails keeps its collision shapes.
async function buildVisuals(sc) {
  const nBodies = sc.dof + 1;
  for (let b = 0; b < nBodies; b++) {
    const g = new THREE.Group();
    bodyObjs.push(g);
    robot.add(g);
  }
  const results = await Promise.all(sc.visuals.map(async (v) => {
    try {
      const obj = v.kind === 'mesh' ? await loadMesh(v.mesh, v.format) : visualPrimitive(v);
      const holder = new THREE.Group();
      holder.position.set(...v.xyz_m);
      holder.quaternion.set(...v.quat_xyzw);
      if (v.kind === 'mesh') holder.scale.set(...v.scale);
      holder.add(obj);
      return { v, holder, error: null };
    } catch (e) {
      return { v, holder: null, error: String(e && e.message || e) };
    }
  }));
  const failedBodies = new Set(results.filter((r) => r.error).map((r) => r.v.body));
  const withVisual = new Set(results.map((r) => r.v.body));
  for (const r of results) {
    if (r.error) {
      const file = r.v.kind === 'mesh' ? sc.meshes[r.v.mesh].file : r.v.kind;
      view.drawn.failed.push(`link ${r.v.link}: ${file} did not load (${r.error})`);
      continue;
    }
    if (failedBodies.has(r.v.body)) continue;
    bodyObjs[r.v.body].add(r.holder);
    visualObjs.push({ link: r.v.link, body: r.v.body, kind: r.v.kind, mesh: r.v.mesh, obj: r.holder });
  }
  const drawnBodies = [...withVisual].filter((b) => !failedBodies.has(b));
  view.drawn.visualBodies = drawnBodies.sort((a, b) => a - b);
  shapeObjs.forEach((o, i) => {
    const s = sc.shapes[i];
    o.userData.replaced = s.role === 'link' && !s.pedestal && drawnBodies.includes(s.body);
    o.visible = !o.userData.replaced;
  });
  view.drawn.visual = visualObjs.length;
  view.drawn.collision = shapeObjs.filter((o, i) => sc.shapes[i].role === 'link' && !o.userData.replaced).length;
  const what = `robot drawn from ${view.drawn.visual} visual element(s) (${visualObjs.filter((v) => v.kind === 'mesh').length} mesh(es)) and ${view.drawn.collision} collision shape(s)`;
  $('drawn').textContent = what + (view.drawn.failed.length ? '; collision shapes instead where a mesh failed: ' + view.drawn.failed.join('; ') : '') +
    (sc.visuals_skipped.length ? '; not drawn: ' + sc.visuals_skipped.join('; ') : '');
  document.body.dataset.drawn = 'yes';
}

function poseArm(poses, bodies) {
  if (!poses) { robot.visible = false; return; }
  robot.visible = true;
  shapeObjs.forEach((o, i) => {
    const k = 7 * i;
    o.position.set(poses[k], poses[k + 1], poses[k + 2]);
    o.quaternion.set(poses[k + 3], poses[k + 4], poses[k + 5], poses[k + 6]);
  });
  if (!bodies) return;
  bodyObjs.forEach((o, i) => {
    const k = 7 * i;
    o.position.set(bodies[k], bodies[k + 1], bodies[k + 2]);
    o.quaternion.set(bodies[k + 3], bodies[k + 4], bodies[k + 5], bodies[k + 6]);
  });
}

// ---- the part: path and bed in the part frame, the group placed at (x, y, z, yaw) ----
const part = new THREE.Group();
scene3.add(part);
let bedMesh = null;
const tipLine = new THREE.Line(new THREE.BufferGeometry(), new THREE.LineBasicMaterial({ color: 0x7a3db8 }));
scene3.add(tipLine);
const reachRing = new THREE.Mesh(new THREE.RingGeometry(0.99, 1.0, 128), new THREE.MeshBasicMaterial({ color: 0x2a6fdb, transparent: true, opacity: 0.5, side: THREE.DoubleSide }));
scene3.add(reachRing);
const mapGroup = new THREE.Group();
scene3.add(mapGroup);

function buildPart(sc) {
  const pts = sc.path.points_m;
  const pos = [];
  const col = [];
  for (let i = 0; i + 1 < pts.length / 3; i++) {
    pos.push(pts[3 * i], pts[3 * i + 1], pts[3 * i + 2], pts[3 * i + 3], pts[3 * i + 4], pts[3 * i + 5]);
    const c = sc.path.print[i + 1] ? [0.15, 0.2, 0.25] : [0.65, 0.7, 0.78];
    col.push(...c, ...c);
  }
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.Float32BufferAttribute(pos, 3));
  g.setAttribute('color', new THREE.Float32BufferAttribute(col, 3));
  part.add(new THREE.LineSegments(g, new THREE.LineBasicMaterial({ vertexColors: true })));
  const lo = sc.bed.lo_m, hi = sc.bed.hi_m;
  bedMesh = new THREE.Mesh(
    new THREE.BoxGeometry(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]),
    new THREE.MeshStandardMaterial({ color: 0x9aa7b4, transparent: true, opacity: 0.55 }));
  bedMesh.position.set((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2);
  part.add(bedMesh);
}

function placePart() {
  const p = view.place;
  part.position.set(p.x_m, p.y_m, p.z_m);
  part.rotation.set(0, 0, p.yaw_deg * Math.PI / 180);
  // Reach at the bed's height: the circle where a sphere of the reach about the base meets it.
  const R = view.scene.reach_m;
  const r = Math.sqrt(Math.max(R * R - p.z_m * p.z_m, 1e-6));
  reachRing.scale.set(r, r, 1);
  reachRing.position.set(0, 0, p.z_m);
  drawMap();
}

// The energy map on the floor: the grid's cells at the bed height nearest the current one,
// least energy over the yaws (green low, red high, grey infeasible).
function drawMap() {
  mapGroup.clear();
  const m = view.scene.map;
  if (!m.length) return;
  const zs = [...new Set(m.map((c) => c.z_m))];
  const z = zs.reduce((a, b) => Math.abs(b - view.place.z_m) < Math.abs(a - view.place.z_m) ? b : a);
  const cells = new Map();
  for (const c of m) {
    if (c.z_m !== z) continue;
    const k = c.x_m + ',' + c.y_m;
    const e = c.energy_j === null ? Infinity : c.energy_j;
    if (!cells.has(k) || e < cells.get(k).e) cells.set(k, { x: c.x_m, y: c.y_m, e });
  }
  const fin = [...cells.values()].map((c) => c.e).filter(isFinite);
  const lo = Math.min(...fin), hi = Math.max(...fin);
  const xs = [...new Set([...cells.values()].map((c) => c.x))].sort((a, b) => a - b);
  const step = xs.length > 1 ? xs[1] - xs[0] : 0.1;
  const geo = new THREE.PlaneGeometry(step * 0.9, step * 0.9);
  for (const c of cells.values()) {
    const t = isFinite(c.e) ? (hi > lo ? (c.e - lo) / (hi - lo) : 0) : -1;
    const colour = t < 0 ? new THREE.Color(0.75, 0.75, 0.75) : new THREE.Color().setHSL(0.33 * (1 - t), 0.8, 0.5);
    const q = new THREE.Mesh(geo, new THREE.MeshBasicMaterial({ color: colour, transparent: true, opacity: 0.75, side: THREE.DoubleSide }));
    // On the floor, where the part's origin would stand over it.
    q.position.set(c.x, c.y, 0.002);
    mapGroup.add(q);
  }
}

// ---- controls ----
const axes = [['x', 'x_m', 3], ['y', 'y_m', 3], ['z', 'z_m', 3], ['yaw', 'yaw_deg', 1]];
function showPlacement() {
  for (const [k, f, d] of axes) {
    $('in-' + k).value = Number(view.place[f]).toFixed(d);
    $('sl-' + k).value = view.place[f];
  }
}
function setPlacement(p, fromInput) {
  Object.assign(view.place, p);
  if (!fromInput) showPlacement();
  placePart();
  requestEval();
}
for (const [k, f] of axes) {
  const take = (el) => () => {
    const v = parseFloat(el.value);
    if (!isFinite(v)) return;
    const p = {}; p[f] = v;
    setPlacement(p, true);
    if (el.id.startsWith('sl')) $('in-' + k).value = v; else $('sl-' + k).value = v;
  };
  $('sl-' + k).addEventListener('input', take($('sl-' + k)));
  $('in-' + k).addEventListener('input', take($('in-' + k)));
  $('in-' + k).addEventListener('change', take($('in-' + k)));
}

// ---- evaluation: one request per animation frame at most; the server drops superseded ones ----
let evalQueued = false, playbackTimer = null;
function requestEval() {
  if (evalQueued) return;
  evalQueued = true;
  requestAnimationFrame(() => { evalQueued = false; sendEval(); });
}
async function sendEval() {
  const seq = ++view.seq;
  const body = Object.assign({ seq }, view.place);
  let v;
  try { v = await postJSON('/api/evaluate', body); } catch (e) { return; }
  if (v.stale || seq < view.applied) return;
  view.applied = seq;
  if (v.error) { $('status').textContent = 'error: ' + v.error; $('status').className = 'bad'; return; }
  view.last = v;
  showEval(v, seq);
  clearTimeout(playbackTimer);
  playbackTimer = setTimeout(() => loadPlayback(seq), 250);
}

// The status line's word on meshes that failed to load (their links drawn from collision shapes).
const drawnNote = () => view.drawn.failed.length ? ` (${view.drawn.failed.length} visual mesh(es) failed to load: collision shapes drawn for ${[...new Set(view.drawn.failed.map((f) => f.split(':')[0]))].join(', ')})` : '';

function showEval(v, seq) {
  $('evalms').textContent = fmt(v.evaluation_s * 1000, 2);
  if (v.feasible) {
    $('supply').textContent = v.supply_text;
    $('drives').textContent = v.drives_text;
    $('standby').textContent = fmt(v.standby_j, 1);
    $('duration').textContent = fmt(v.duration_s, 2);
    $('status').textContent = 'feasible' + drawnNote();
    $('status').className = 'ok';
    $('reason').textContent = '';
    const mx = Math.max(...v.joints.map((j) => Math.abs(j.electrical_j || 0)), 1e-9);
    $('bars').innerHTML = v.joints.map((j) =>
      `<div class="bar"><span>${j.name}</span><div><div class="b" style="width:${(100 * Math.abs(j.electrical_j || 0) / mx).toFixed(1)}%"></div></div><span>${fmt(j.electrical_j, 1)} J</span></div>`).join('');
    const m = v.margins;
    $('margins').innerHTML =
      `<tr><td>joint limit</td><td>${m.joint ? 'joint ' + m.joint.joint + ' (' + m.joint.name + '), ' + fmt(m.joint.deg, 1) + '°' : 'n/a'}</td></tr>` +
      `<tr><td>wrist</td><td>${fmt(m.wrist_deg, 1)}° from the singularity</td></tr>` +
      `<tr><td>bed clearance</td><td>${m.clearance_m === null ? 'n/a' : fmt(m.clearance_m * 1000, 0) + ' mm'}</td></tr>` +
      `<tr><td>elbow</td><td>${fmt(m.elbow, 3)}</td></tr>` +
      `<tr><td>shoulder</td><td>${m.shoulder_m === null ? 'n/a' : fmt(m.shoulder_m, 3) + ' m'}</td></tr>`;
  } else {
    const i = v.infeasible;
    $('supply').textContent = '—';
    $('drives').textContent = '—';
    $('standby').textContent = '—';
    $('duration').textContent = '—';
    $('status').textContent = 'INFEASIBLE: ' + i.reason + drawnNote();
    $('status').className = 'bad';
    $('reason').textContent = i.text;
    $('bars').innerHTML = '';
    $('margins').innerHTML = '';
  }
  document.body.dataset.evalSeq = String(seq);
  document.body.dataset.feasible = String(v.feasible);
}

// ---- playback ----
let playing = false, frame = 0, playStart = 0;
async function loadPlayback(seq) {
  if (seq !== view.applied) return;
  const v = await postJSON('/api/playback', Object.assign({ frames: 240 }, view.place));
  if (seq !== view.applied) return;
  view.playback = v.timed ? v : null;
  if (!v.timed) { poseArm(null); tipLine.visible = false; drawTrace(); return; }
  $('frame').max = String(v.t_s.length - 1);
  const tp = v.tip_m;
  tipLine.geometry.dispose();
  tipLine.geometry = new THREE.BufferGeometry();
  tipLine.geometry.setAttribute('position', new THREE.Float32BufferAttribute(tp, 3));
  tipLine.visible = true;
  frame = Math.min(frame, v.t_s.length - 1);
  showFrame(frame);
}
function showFrame(k) {
  const pb = view.playback;
  if (!pb) return;
  frame = k;
  poseArm(pb.poses[k], pb.bodies && pb.bodies[k]);
  $('frame').value = String(k);
  $('ptime').textContent = 't = ' + fmt(pb.t_s[k], 1) + ' s of ' + fmt(pb.duration_s, 1) + ' s';
  drawTrace();
}
function drawTrace() {
  const c = $('trace'), g = c.getContext('2d');
  g.clearRect(0, 0, c.width, c.height);
  const pb = view.playback;
  if (!pb) return;
  const t = pb.power.t_s, p = pb.power.supply_w;
  const T = t[t.length - 1] || 1, lo = Math.min(0, ...p), hi = Math.max(...p, 1);
  const X = (x) => 4 + (c.width - 8) * x / T, Y = (y) => c.height - 12 - (c.height - 20) * (y - lo) / (hi - lo);
  g.strokeStyle = '#3a78c2'; g.beginPath();
  t.forEach((x, i) => (i ? g.lineTo(X(x), Y(p[i])) : g.moveTo(X(x), Y(p[i]))));
  g.stroke();
  g.strokeStyle = '#b3261e'; g.beginPath();
  const tc = pb.t_s[frame] || 0;
  g.moveTo(X(tc), 0); g.lineTo(X(tc), c.height); g.stroke();
  g.fillStyle = '#556'; g.font = '10px sans-serif';
  g.fillText('supply power, W (max ' + fmt(hi, 0) + ')', 6, c.height - 2);
}
$('frame').addEventListener('input', (e) => showFrame(parseInt(e.target.value, 10)));
$('play').addEventListener('click', () => {
  playing = !playing;
  $('play').textContent = playing ? 'pause' : 'play';
  playStart = performance.now() - frame * 40;
});

// ---- optimise, jump, export ----
let answer = null;
$('optimise').addEventListener('click', async () => {
  await postJSON('/api/optimise', {});
  $('optimise').disabled = true;
  const poll = async () => {
    const s = await getJSON('/api/optimise');
    if (s.state === 'running') {
      $('opt-progress').textContent = (s.stage || 'starting') + ' ' + s.done + '/' + s.total + (s.best_j ? ', best ' + fmt(s.best_j, 1) + ' J' : '');
      setTimeout(poll, 400);
      return;
    }
    $('optimise').disabled = false;
    if (s.state === 'done') {
      answer = s.answer;
      const p = answer.placement;
      $('opt-progress').textContent = `answer: x ${fmt(p.x_m, 3)} m, y ${fmt(p.y_m, 3)} m, z ${fmt(p.z_m, 3)} m, yaw ${fmt(p.yaw_deg, 1)}°: supply ${answer.supply_text} J (${fmt(s.secs, 1)} s)`;
      $('jump').disabled = false;
    } else {
      $('opt-progress').textContent = 'failed: ' + s.error;
    }
  };
  poll();
});
$('jump').addEventListener('click', () => { if (answer) setPlacement(answer.placement); });
$('export').addEventListener('click', async () => {
  const v = await postJSON('/api/export', view.place);
  $('export-status').textContent = v.error ? 'not exported: ' + v.error : 'written: ' + v.written.join(', ');
  document.body.dataset.exported = v.error ? 'error' : 'yes';
});

// ---- dragging the part on the plane of its bed ----
const ray = new THREE.Raycaster();
let drag = null;
function planeHit(ev) {
  const r = renderer.domElement.getBoundingClientRect();
  const ndc = new THREE.Vector2(((ev.clientX - r.left) / r.width) * 2 - 1, -((ev.clientY - r.top) / r.height) * 2 + 1);
  ray.setFromCamera(ndc, camera);
  const plane = new THREE.Plane(new THREE.Vector3(0, 0, 1), -view.place.z_m);
  const hit = new THREE.Vector3();
  return { hit: ray.ray.intersectPlane(plane, hit) ? hit : null, ndc };
}
renderer.domElement.addEventListener('pointerdown', (ev) => {
  if (!bedMesh) return;
  const { hit } = planeHit(ev);
  const onPart = ray.intersectObject(bedMesh, false).length > 0;
  if (!onPart || !hit) return;
  controls.enabled = false;
  drag = { start: hit.clone(), place: Object.assign({}, view.place), turn: ev.shiftKey };
  renderer.domElement.setPointerCapture(ev.pointerId);
});
renderer.domElement.addEventListener('pointermove', (ev) => {
  if (!drag) return;
  const { hit } = planeHit(ev);
  if (!hit) return;
  if (drag.turn) {
    const a0 = Math.atan2(drag.start.y - drag.place.y_m, drag.start.x - drag.place.x_m);
    const a1 = Math.atan2(hit.y - drag.place.y_m, hit.x - drag.place.x_m);
    let yaw = drag.place.yaw_deg + (a1 - a0) * 180 / Math.PI;
    yaw = ((yaw + 540) % 360) - 180;
    setPlacement({ yaw_deg: Math.round(yaw * 10) / 10 });
  } else {
    const r3 = (x) => Math.round(x * 1000) / 1000;
    setPlacement({ x_m: r3(drag.place.x_m + hit.x - drag.start.x), y_m: r3(drag.place.y_m + hit.y - drag.start.y) });
  }
});
const endDrag = () => { drag = null; controls.enabled = true; };
renderer.domElement.addEventListener('pointerup', endDrag);
renderer.domElement.addEventListener('pointercancel', endDrag);

function draw(now) {
  drawQueued = false;
  if (playing && view.playback) {
    const n = view.playback.t_s.length;
    const k = Math.floor((now - playStart) / 40) % n;
    if (k !== frame) showFrame(k);
    requestDraw();
  }
  controls.update();
  renderer.render(scene3, camera);
}

// Where a point of the base frame (m) is on the page, in CSS pixels (for scripted drags).
view.screenOf = (x, y, z) => {
  const v = new THREE.Vector3(x, y, z).project(camera);
  const r = renderer.domElement.getBoundingClientRect();
  return [r.left + (v.x + 1) / 2 * r.width, r.top + (1 - v.y) / 2 * r.height];
};
// The centre of the bed's top face on the page.
// The drawn collision mesh pieces of the links (a link may be several convex pieces), for tests.
view.hullPieces = () => shapeObjs.filter((o) => !o.userData.replaced && o.children.some((c) => c.userData.hull)).length;
// Each visual element drawn: its link, body, kind and box in its body's frame (m), for tests.
view.visualBoxes = () => visualObjs.map((v) => {
  const body = bodyObjs[v.body];
  robot.updateMatrixWorld(true);
  const inv = body.matrixWorld.clone().invert();
  const box = new THREE.Box3();
  v.obj.traverse((m) => {
    if (!m.isMesh) return;
    m.geometry.computeBoundingBox();
    box.union(m.geometry.boundingBox.clone().applyMatrix4(inv.clone().multiply(m.matrixWorld)));
  });
  return { link: v.link, body: v.body, kind: v.kind, mesh: v.mesh, min: box.min.toArray(), max: box.max.toArray() };
});
view.bedScreen = () => {
  const b = bedMesh.geometry.parameters;
  const c = part.localToWorld(bedMesh.position.clone().add(new THREE.Vector3(0, 0, b.depth / 2)));
  return view.screenOf(c.x, c.y, c.z);
};
// The evaluation shown is of the placement shown and nothing is on its way.
view.settled = () => !evalQueued && view.applied === view.seq && view.last !== null &&
  ['x_m', 'y_m', 'z_m', 'yaw_deg'].every((k) => Math.abs(view.last.placement[k] - view.place[k]) < 1e-9);

async function main() {
  const sc = await getJSON('/api/scene');
  view.scene = sc;
  $('what').textContent = `${sc.robot}, ${sc.path_file} (${sc.path.samples} samples); objective: ${sc.objective_text}` + (sc.export_dir ? `; export to ${sc.export_dir}` : '');
  for (const s of sc.shapes) {
    const o = shapeMesh(s);
    shapeObjs.push(o);
    robot.add(o);
  }
  robot.visible = false;
  await buildVisuals(sc);
  buildPart(sc);
  const R = sc.reach_m;
  for (const k of ['x', 'y']) { $('sl-' + k).min = -R; $('sl-' + k).max = R; }
  $('sl-z').min = -0.5 * R; $('sl-z').max = R;
  const grid = new THREE.GridHelper(4 * R, 40, 0xb0b8c0, 0xd0d6dc);
  grid.rotation.x = Math.PI / 2;
  scene3.add(grid);
  scene3.add(new THREE.AxesHelper(0.3 * R));
  camera.position.set(1.3 * R, -1.6 * R, 1.2 * R);
  controls.target.set(0.35 * R, 0, 0.25 * R);
  resize();
  setPlacement(sc.start);
  view.ready = true;
  document.body.dataset.ready = 'yes';
  requestDraw();
}
main().catch((e) => { $('status').textContent = 'error: ' + e; $('status').className = 'bad'; });
