//! Forward kinematics and the Jacobian checked against two independent implementations:
//! the committed pinocchio 4.1 reference poses (`tests/data/pinocchio/<robot>.csv`, columns
//! `x,y,z,r11..r33`: the `tool_link` frame in the base frame) and the `k` crate (openrr) with
//! its own URDF reader, on every shipped robot. `k` uses nalgebra 0.30; values cross over as
//! arrays.

use printwatt::kinematics::{flange_pose, jacobian};
use rand::{Rng, SeedableRng};
use std::path::{Path, PathBuf};

const ROBOTS: [&str; 5] = [
    "abb_irb4600_40_255",
    "abb_irb6700_200_260",
    "puma560",
    "staubli_tx200",
    "ur10e",
];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn robot(name: &str) -> printwatt::RobotModel {
    printwatt::load_robot(&root().join("robots").join(name)).unwrap()
}

#[test]
fn fk_matches_the_committed_pinocchio_poses_of_every_shipped_robot() {
    for name in ROBOTS {
        let m = robot(name);
        let text = std::fs::read_to_string(root().join(format!("tests/data/pinocchio/{name}.csv")))
            .unwrap();
        let mut lines = text.lines().filter(|l| !l.starts_with('#'));
        let head: Vec<&str> = lines.next().unwrap().split(',').collect();
        let col = |c: &str| head.iter().position(|h| *h == c).unwrap();
        let q0 = col("q1");
        let x0 = col("x");
        let r0 = col("r11");
        let (mut rows, mut worst_p, mut worst_r) = (0, 0.0f64, 0.0f64);
        for l in lines {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            let f = flange_pose(&m, &v[q0..q0 + 6]);
            for i in 0..3 {
                worst_p = worst_p.max((f.pos[i] - v[x0 + i]).abs());
                for j in 0..3 {
                    // r11 r12 r13 r21 …: row-major.
                    worst_r = worst_r.max((f.rot[(i, j)] - v[r0 + 3 * i + j]).abs());
                }
            }
            rows += 1;
        }
        assert_eq!(rows, 1000, "{name}");
        assert!(
            worst_p < 1e-9 && worst_r < 1e-9,
            "{name}: {worst_p} m, {worst_r}"
        );
    }
}

/// The `k` chain of a robot's URDF, the node of its flange link and the node of each arm
/// joint (by the names printwatt's model gives them).
fn k_chain(m: &printwatt::RobotModel, urdf: &Path) -> (k::Chain<f64>, String) {
    let chain = k::Chain::<f64>::from_urdf_file(urdf).unwrap();
    (chain, m.flange_link.clone())
}

#[test]
fn fk_and_jacobian_agree_with_the_k_crate_on_every_shipped_robot() {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
    for name in ROBOTS {
        let m = robot(name);
        let (chain, flange) = k_chain(&m, &root().join("robots").join(name).join("robot.urdf"));
        let end = chain
            .find_link(&flange)
            .unwrap_or_else(|| panic!("{name}: k has no link {flange}"));
        let arm = k::SerialChain::from_end(end);
        let arm_names: Vec<String> = arm.iter_joints().map(|j| j.name.clone()).collect();
        let ours: Vec<&str> = m.joints.iter().map(|j| j.name.as_str()).collect();
        assert_eq!(
            arm_names, ours,
            "{name}: the two readers find the same arm joints"
        );
        let (mut worst_p, mut worst_r, mut worst_j) = (0.0f64, 0.0f64, 0.0f64);
        for _ in 0..200 {
            let q: Vec<f64> = m
                .joints
                .iter()
                .map(|j| {
                    let (lo, hi) = (j.lower.max(-6.0), j.upper.min(6.0));
                    rng.gen_range(lo..=hi)
                })
                .collect();
            // Unchecked: the ABB balancer cylinder mimics joint 2 with its own (tighter) limits.
            arm.set_joint_positions_unchecked(&q);
            arm.update_transforms();
            let t = end.world_transform().unwrap();
            let f = flange_pose(&m, &q);
            let rk = t.rotation.to_rotation_matrix();
            for i in 0..3 {
                worst_p = worst_p.max((f.pos[i] - t.translation.vector[i]).abs());
                for j in 0..3 {
                    worst_r = worst_r.max((f.rot[(i, j)] - rk[(i, j)]).abs());
                }
            }
            // k's Jacobian is of the flange origin; ours of the nozzle tip: move k's to the tip
            // with v_tip = v_flange + ω × (p_tip − p_flange).
            let jk = k::jacobian(&arm);
            let tip = printwatt::kinematics::tool_pose(&m, &q).pos;
            let r = [tip[0] - f.pos[0], tip[1] - f.pos[1], tip[2] - f.pos[2]];
            let jo = jacobian(&m, &q);
            for c in 0..6 {
                let w = [jk[(3, c)], jk[(4, c)], jk[(5, c)]];
                let lin = [
                    jk[(0, c)] + w[1] * r[2] - w[2] * r[1],
                    jk[(1, c)] + w[2] * r[0] - w[0] * r[2],
                    jk[(2, c)] + w[0] * r[1] - w[1] * r[0],
                ];
                for i in 0..3 {
                    worst_j = worst_j.max((jo.cols[c][i] - lin[i]).abs());
                    worst_j = worst_j.max((jo.cols[c][3 + i] - w[i]).abs());
                }
            }
        }
        assert!(
            worst_p < 1e-9 && worst_r < 1e-9 && worst_j < 1e-9,
            "{name}: position {worst_p} m, rotation {worst_r}, Jacobian {worst_j}"
        );
    }
}
