//! The identification loop on a shipped robot (ABB IRB 4600-40/2.55) with simulated logs:
//! every catalogue effect hidden in a log is ranked first by `diagnose` and cuts the held-out
//! RMSE by ≥ 80 %; two hidden effects are found one after the other; a log without hidden
//! effects gets no claim; bad logs give errors naming file, line and column; an
//! ill-conditioned fit names the parameters it cannot tell apart; JSON outputs parse.

use printwatt::identify::{
    diagnose::diagnose,
    fit::fit,
    log::{parse_log, SignalKind},
    simulate, Model, Prepared,
};
use printwatt::robot;
use std::path::PathBuf;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn robot_dir() -> PathBuf {
    root().join("robots/abb_irb4600_40_255")
}

fn nominal() -> (robot::RobotModel, Model) {
    let r = robot::load(&robot_dir()).unwrap();
    let m = Model::new(&r).unwrap();
    (r, m)
}

/// A simulated log text: 8 s of exciting motion at 250 Hz with realistic noise.
fn sim(hidden: &str, kind: SignalKind, noise: f64, seed: u64) -> String {
    let (r, mut truth) = nominal();
    simulate::apply_hidden(&mut truth, &simulate::parse_hidden(hidden).unwrap()).unwrap();
    let tr = simulate::resample(&simulate::excitation(&r, 8.0, 1000.0, seed), 250.0);
    let opt = simulate::SensorOptions {
        kind,
        noise,
        noise_q: 1e-6,
        current_quantum: 0.01,
        seed,
    };
    simulate::simulate_log(&truth, &tr, &opt, &[]).unwrap()
}

fn diagnosis_of(text: &str) -> printwatt::identify::diagnose::Diagnosis {
    let (_, mut m) = nominal();
    let log = parse_log(text, "sim.csv", 6, None).unwrap();
    let prep = Prepared::new(&m, &log).unwrap();
    diagnose(&prep, &mut m, 4).unwrap()
}

#[test]
fn each_hidden_effect_is_ranked_first_and_cuts_the_error() {
    let cases: [(&str, &str, SignalKind, f64); 10] = [
        ("viscous", "viscous=40", SignalKind::Torque, 2.0),
        ("coulomb", "coulomb=30", SignalKind::Torque, 2.0),
        ("stribeck", "stribeck=60:0.1", SignalKind::Torque, 2.0),
        ("armature", "armature=40", SignalKind::Torque, 1.0),
        ("payload", "payload=15", SignalKind::Torque, 2.0),
        ("balancer", "balancer=3000:20000", SignalKind::Torque, 2.0),
        ("copper", "copper=3", SignalKind::AxisPower, 2.0),
        (
            "gear_efficiency",
            "gear_efficiency=-0.15",
            SignalKind::AxisPower,
            2.0,
        ),
        (
            "regeneration",
            "regeneration=1",
            SignalKind::TotalPower,
            5.0,
        ),
        ("standby", "standby=300", SignalKind::TotalPower, 5.0),
    ];
    let mut failures = Vec::new();
    for (i, (name, hidden, kind, noise)) in cases.iter().enumerate() {
        let d = diagnosis_of(&sim(hidden, *kind, *noise, 10 + i as u64));
        let top = &d.candidates[0];
        if d.best.as_deref() != Some(*name) || top.rmse_cut_pct < 80.0 {
            failures.push(format!(
                "{name}: best {:?}, top {} cut {:.1} %, t {:.2}",
                d.best, top.effect, top.rmse_cut_pct, top.t_statistic
            ));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

#[test]
fn two_hidden_effects_are_found_one_after_the_other() {
    let text = sim("coulomb=30,balancer=3000:20000", SignalKind::Torque, 2.0, 3);
    let (_, mut m) = nominal();
    let log = parse_log(&text, "two.csv", 6, None).unwrap();
    let prep = Prepared::new(&m, &log).unwrap();
    let d1 = diagnose(&prep, &mut m, 4).unwrap();
    assert_eq!(d1.best.as_deref(), Some("balancer"), "{}", d1.verdict);
    let all: Vec<usize> = (0..log.len()).collect();
    fit(&prep, &mut m, &["balancer"], &all).unwrap();
    let d2 = diagnose(&prep, &mut m, 4).unwrap();
    assert_eq!(d2.best.as_deref(), Some("coulomb"), "{}", d2.verdict);
    assert!(d2.candidates[0].rmse_cut_pct >= 80.0);
    fit(&prep, &mut m, &["balancer", "coulomb"], &all).unwrap();
    let d3 = diagnose(&prep, &mut m, 4).unwrap();
    assert!(d3.best.is_none(), "{}", d3.verdict);
}

#[test]
fn no_hidden_effect_no_claim() {
    for kind in [SignalKind::Torque, SignalKind::TotalPower] {
        let d = diagnosis_of(&sim(
            "",
            kind,
            if kind == SignalKind::Torque { 2.0 } else { 5.0 },
            5,
        ));
        assert!(d.best.is_none(), "{kind:?}: {}", d.verdict);
        assert!(d.verdict.contains("nothing significant"));
    }
}

fn err(text: &str) -> String {
    parse_log(text, "bad.csv", 6, None).unwrap_err().to_string()
}

fn good_rows(k: usize) -> String {
    (0..k)
        .map(|i| format!("{},0,0,0,0,0,0,1,1,1,1,1,1\n", i as f64 * 0.01))
        .collect()
}

const HEAD: &str = "t,q1,q2,q3,q4,q5,q6,tau1,tau2,tau3,tau4,tau5,tau6\n";

#[test]
fn bad_logs_name_file_line_and_column() {
    // Joint count.
    let e = err(&format!(
        "t,q1,q2,q3,q4,q5,tau1\n{}",
        "0,0,0,0,0,0,1\n".repeat(60)
    ));
    assert!(
        e.contains("bad.csv") && e.contains("got 5") && e.contains("expected 6"),
        "{e}"
    );
    // Unknown unit.
    let e = err(&format!(
        "t,q1[furlong],q2,q3,q4,q5,q6,tau1,tau2,tau3,tau4,tau5,tau6\n{}",
        good_rows(60)
    ));
    assert!(
        e.starts_with("bad.csv:1:3:") && e.contains("furlong"),
        "{e}"
    );
    // Gap (empty cell) on line 5, column of q2.
    let mut rows = good_rows(60);
    rows = rows.replacen("0.03,0,0", "0.03,0,", 1);
    let e = err(&format!("{HEAD}{rows}"));
    assert!(e.starts_with("bad.csv:5:") && e.contains("q2"), "{e}");
    // NaN.
    let rows = good_rows(60).replacen("0.04,0,0,0", "0.04,0,0,NaN", 1);
    let e = err(&format!("{HEAD}{rows}"));
    assert!(e.starts_with("bad.csv:6:") && e.contains("q3"), "{e}");
    // Repeated time stamp.
    let rows = good_rows(60).replacen("0.02,", "0.01,", 1);
    let e = err(&format!("{HEAD}{rows}"));
    assert!(
        e.starts_with("bad.csv:4:1:") && e.contains("not after"),
        "{e}"
    );
    // Too few samples.
    let e = err(&format!("{HEAD}{}", good_rows(10)));
    assert!(e.contains("bad.csv") && e.contains("at least"), "{e}");
    // No signal.
    let rows: String = (0..60).map(|i| format!("{i},0,0,0,0,0,0\n")).collect();
    let e = err(&format!("t,q1,q2,q3,q4,q5,q6\n{rows}"));
    assert!(e.contains("no compared signal"), "{e}");
    // Fixture files.
    for f in [
        "gap.csv",
        "nan.csv",
        "repeated_t.csv",
        "five_joints.csv",
        "short.csv",
    ] {
        let p = root().join("tests/data/logs").join(f);
        let e = printwatt::identify::read_log(&p, 6, None)
            .unwrap_err()
            .to_string();
        assert!(e.contains(f), "{f}: {e}");
    }
}

#[test]
fn column_map_reads_headerless_export_and_warns_unknown() {
    let body: String = (0..60)
        .map(|i| format!("{},0,0,0,0,0,0,1,1,1,1,1,1,9,9\n", i as f64 * 4.0))
        .collect();
    let log = parse_log(
        &body,
        "ctl.txt",
        6,
        Some("t[ms], q1..q6[deg], tau1..tau6, skip*2"),
    )
    .unwrap();
    assert_eq!(log.len(), 60);
    assert!((log.traj.t[1] - 0.004).abs() < 1e-12);
    let e = parse_log(
        &body.replacen("4,0", "4,x", 1),
        "ctl.txt",
        6,
        Some("t[ms], q1..q6[deg], tau1..tau6, skip*2"),
    )
    .unwrap_err()
    .to_string();
    assert!(e.starts_with("ctl.txt:2:"), "{e}");
    let log = parse_log(
        &format!(
            "t,q1,q2,q3,q4,q5,q6,tau1,tau2,tau3,tau4,tau5,tau6,temp\n{}",
            good_rows(60).replace('\n', ",20\n")
        ),
        "u.csv",
        6,
        None,
    )
    .unwrap();
    assert_eq!(log.warnings.len(), 1);
    assert!(log.warnings[0].contains("temp"));
}

#[test]
fn ill_conditioned_fit_names_parameters() {
    // Joint 6 held still: its viscous and Coulomb parameters are not excited.
    let text = sim("", SignalKind::Torque, 2.0, 9);
    let mut out = String::new();
    for line in text.lines() {
        if line.starts_with('t') || line.starts_with('#') {
            out.push_str(line);
        } else {
            let mut c: Vec<&str> = line.split(',').collect();
            c[6] = "0.1";
            out.push_str(&c.join(","));
        }
        out.push('\n');
    }
    let (_, mut m) = nominal();
    let log = parse_log(&out, "still6.csv", 6, None).unwrap();
    let prep = Prepared::new(&m, &log).unwrap();
    let all: Vec<usize> = (0..log.len()).collect();
    let r = fit(&prep, &mut m, &["viscous", "coulomb"], &all).unwrap();
    let ill = r.ill_conditioned.expect("ill-conditioned");
    let msg = ill.to_string();
    assert!(
        msg.contains("viscous.f_v[6]") && msg.contains("coulomb.f_c+[6]"),
        "{msg}"
    );
}

#[test]
fn regressor_times_params_equals_contribution() {
    use printwatt::effects::{Balancer, Effect, Payload};
    let (r, _) = nominal();
    let mut p = Payload::new(&r).unwrap();
    p.dm = 7.0;
    let b = Balancer {
        preload: 2000.0,
        stiffness: 1e4,
        ..Balancer::zero()
    };
    let (q, qd, qdd) = ([0.1, 0.4, -0.3, 0.2, 0.5, 0.1], [0.3; 6], [0.7; 6]);
    p.dh = [0.4, -0.3, 1.2];
    p.di = [0.05, -0.02, 0.03, 0.01, 0.0, -0.01];
    for (e, np) in [(&p as &dyn Effect, 10usize), (&b, 2)] {
        let mut tau = [0.0; 6];
        e.add_torque(&q, &qd, &qdd, &mut tau);
        let mut y = vec![0.0; 6 * np];
        assert!(e.regressor(&q, &qd, &qdd, &mut y));
        let v = e.values();
        for j in 0..6 {
            let s: f64 = (0..np).map(|k| y[j * np + k] * v[k]).sum();
            assert!(
                (s - tau[j]).abs() < 1e-9 * (1.0 + tau[j].abs()),
                "{} joint {j}",
                e.name()
            );
        }
    }
}

#[test]
fn cli_json_outputs_parse() {
    let dir = std::env::temp_dir().join(format!("printwatt_ident_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let log = dir.join("log.csv");
    std::fs::write(&log, sim("payload=15", SignalKind::Torque, 2.0, 4)).unwrap();
    let bin = env!("CARGO_BIN_EXE_printwatt");
    let robot_copy = dir.join("robot");
    std::fs::create_dir_all(&robot_copy).unwrap();
    for e in std::fs::read_dir(robot_dir()).unwrap() {
        let p = e.unwrap().path();
        if p.is_file() {
            std::fs::copy(&p, robot_copy.join(p.file_name().unwrap())).unwrap();
        }
    }
    let run = |args: &[&str]| {
        let o = std::process::Command::new(bin)
            .current_dir(&dir)
            .args(args)
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        serde_json::from_slice::<serde_json::Value>(&o.stdout).unwrap()
    };
    let (r, l) = (robot_copy.to_str().unwrap(), log.to_str().unwrap());
    let c = run(&["compare", "--robot", r, "--log", l, "--json"]);
    assert!(c["total"]["rmse"].as_f64().unwrap() > 0.0);
    let d = run(&["diagnose", "--robot", r, "--log", l, "--json"]);
    assert_eq!(d["best"], "payload");
    let i = run(&[
        "identify",
        "--robot",
        r,
        "--log",
        l,
        "--effects",
        "payload",
        "--json",
    ]);
    let lad = i["identification"]["ladder"].as_array().unwrap();
    assert_eq!(lad.len(), 2);
    assert_eq!(i["schema_version"], 1);
    // Written into the current directory (no --out), never beside the input.
    let calibrated = dir.join("robot.calibrated.toml");
    assert!(calibrated.is_file());
    assert!(!robot_copy.join("drive.identified.toml").exists());
    // Refuses to overwrite without --force.
    let o = std::process::Command::new(bin)
        .current_dir(&dir)
        .args(["identify", "--robot", r, "--log", l, "--effects", "payload"])
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("--force"));
    // The identified file loads and leaves nothing significant.
    let d = run(&[
        "diagnose",
        "--robot",
        calibrated.to_str().unwrap(),
        "--log",
        l,
        "--json",
    ]);
    assert!(d["best"].is_null(), "{}", d["verdict"]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// "rigid_body a near-equal second to the true balancer, marked significant, with a link-3 mass
/// of −79 kg" (results/identify_example): a fit that describes no physical robot is named but
/// not claimed, and diagnose says why. Hidden balancer error + Coulomb friction (the worked
/// example's log, 8 s): `rigid_body` cuts the held-out error by as much as a claim needs, but
/// no physical robot has its base parameters (as fitted, link 3 weighs −15 kg; no realisation
/// of the same base parameters has every link's pseudo-inertia positive semidefinite), so it
/// is not significant and `balancer` is claimed. Directly on the effect: the mirrored rigid
/// body (base parameters negated) is implausible, the nominal scaled by 1.05 is plausible, an
/// error within two standard errors is not judged, and an inertia no mass distribution has is
/// named.
#[test]
fn rigid_body_with_a_negative_link_mass_is_not_claimed() {
    let d = diagnosis_of(&sim(
        "coulomb=30,balancer=3000:20000",
        SignalKind::Torque,
        2.0,
        7,
    ));
    let rb = d
        .candidates
        .iter()
        .find(|c| c.effect == "rigid_body")
        .unwrap();
    let why = rb.implausible.as_deref().unwrap_or("");
    assert!(
        !rb.plausible && !rb.significant && why.contains("no physical robot has"),
        "rigid_body: cut {:.1} %, plausible {}, {why}",
        rb.rmse_cut_pct,
        rb.plausible
    );
    // It would have passed the statistical criteria: only plausibility stops the claim.
    assert!(
        rb.rmse_cut_pct > 50.0 && rb.delta_bic < -10.0,
        "{}",
        d.verdict
    );
    assert_eq!(d.best.as_deref(), Some("balancer"), "{}", d.verdict);

    // The check itself, on the effect.
    let (r, _) = nominal();
    let set = printwatt::effects::EffectSet::of_robot(&r).unwrap();
    let rb = set
        .typed::<printwatt::effects::RigidBody>("rigid_body")
        .unwrap();
    let beta = rb.nominal_base_values().to_vec();
    let mut rbe = rb.clone();
    use printwatt::effects::Effect;
    let p = beta.len();
    let se = vec![Some(1e-3); p];
    // The mirrored robot (every torque negated: gravity pulls up) is no physical robot.
    let mirror: Vec<f64> = beta.iter().map(|b| -2.0 * b).collect();
    rbe.set_values(&mirror).unwrap();
    let why = rbe.implausible_fit(&se).unwrap_or_default();
    assert!(why.contains("no physical robot has"), "{why}");
    // Every base parameter 5 % larger: the nominal robot scaled, plausible.
    let scaled: Vec<f64> = beta.iter().map(|b| 0.05 * b).collect();
    rbe.set_values(&scaled).unwrap();
    assert_eq!(rbe.implausible_fit(&se), None);
    // The mirror within two standard errors of the nominal: not judged.
    let wide: Vec<Option<f64>> = mirror.iter().map(|m| Some(m.abs())).collect();
    rbe.set_values(&mirror).unwrap();
    assert_eq!(rbe.implausible_fit(&wide), None);
    // A large negative moment on link 2: an inertia no mass distribution has.
    let names: Vec<String> = rbe.params().iter().map(|p| p.name.clone()).collect();
    let i2 = names
        .iter()
        .position(|n| ["L2.Ixx", "L2.Iyy", "L2.Izz"].contains(&n.as_str()))
        .unwrap();
    let mut v = vec![0.0; p];
    v[i2] = -1e3;
    rbe.set_values(&v).unwrap();
    let why = rbe.implausible_fit(&se).unwrap_or_default();
    assert!(
        why.contains("inertia is not physically consistent"),
        "{why}"
    );
}

#[test]
fn identify_writes_report_html_listing_every_fitted_parameter() {
    // The worked example's log (results/identify_example/), round 1: the balancer.
    let d = std::env::temp_dir().join(format!("printwatt-identify-report-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_printwatt"))
        .current_dir(&root)
        .args(["identify", "--robot", "abb_irb4600_40_255", "--log"])
        .arg(root.join("results/identify_example/log.csv"))
        .args(["--effects", "balancer", "--out"])
        .arg(d.join("out"))
        .arg("--drive-out")
        .arg(d.join("robot.calibrated.toml"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let html = std::fs::read_to_string(d.join("out/report.html")).expect("report.html written");
    assert!(d.join("out/ladder.svg").is_file());
    let doc = roxmltree::Document::parse_with_options(
        &html,
        roxmltree::ParsingOptions {
            allow_dtd: true,
            ..Default::default()
        },
    )
    .expect("report.html is well-formed XML");
    let id: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("out/identify.json")).unwrap())
            .unwrap();
    // Every fitted parameter is a row of the parameters' table, with its standard error and
    // plausibility.
    let rows: Vec<Vec<String>> = doc
        .descendants()
        .filter(|n| n.has_tag_name("tr"))
        .map(|tr| {
            tr.children()
                .filter(|c| c.has_tag_name("td"))
                .map(|c| c.text().unwrap_or("").to_string())
                .collect()
        })
        .collect();
    let params = id["params"].as_array().unwrap();
    assert!(!params.is_empty());
    for p in params {
        let (e, n) = (p["effect"].as_str().unwrap(), p["name"].as_str().unwrap());
        let row = rows
            .iter()
            .find(|r| r.len() == 8 && r[0] == e && r[1] == n)
            .unwrap_or_else(|| panic!("{e}.{n} not listed"));
        if let Some(se) = p["std_error"].as_f64() {
            let shown: f64 = row[5].parse().unwrap();
            assert!(
                (shown - se).abs() <= 1e-6 * se.abs().max(1.0),
                "{row:?} vs {se}"
            );
        }
        assert!(row[7] == "yes" || !row[7].is_empty(), "{row:?}");
    }
    // The rounds, the error per joint before and after (6 joints and the total), the ladder.
    for h in [
        "Rounds",
        "Fitted parameters",
        "Error per joint, before and after the fit",
        "Error ladder",
    ] {
        assert!(html.contains(&format!("<h2>{h}</h2>")), "{h}");
    }
    let per_joint: Vec<&Vec<String>> = rows
        .iter()
        .filter(|r| r.len() == 5 && r[0].starts_with("joint_"))
        .collect();
    assert_eq!(per_joint.len(), 6, "{rows:?}");
    // The balancer cuts the error of joint 2 (the balanced axis).
    let j2 = per_joint.iter().find(|r| r[0] == "joint_2").unwrap();
    let (before, after): (f64, f64) = (j2[1].parse().unwrap(), j2[2].parse().unwrap());
    assert!(after < before, "{j2:?}");
    let figs: Vec<&str> = doc
        .descendants()
        .filter(|n| n.has_tag_name("figure"))
        .filter_map(|n| n.attribute("id"))
        .collect();
    assert_eq!(figs, ["per-joint", "ladder"]);
    // The drive data's status is stated.
    assert!(
        html.contains("<dt>drive data</dt><dd>ESTIMATE: "),
        "drive data status"
    );
    let _ = std::fs::remove_dir_all(&d);
}
