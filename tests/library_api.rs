//! The pieces that used to live in the CLI and are now library functions (issue 11, item 1):
//! one placement parser, derivative completion, the train/validation split. None of their
//! errors names a command-line flag.

use printwatt::dynamics::complete_derivatives;
use printwatt::toolpath::{Placement, PlacementParseError};
use printwatt::trajectory::{JointTrajectory, Supplied};

#[test]
fn one_placement_parser_takes_an_optional_spin_and_refuses_nan() {
    let p = Placement::parse("1.7, 0,0.2,90").unwrap();
    assert_eq!((p.x, p.y, p.z), (1.7, 0.0, 0.2));
    assert!((p.yaw - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
    assert_eq!(p.nozzle_spin, 0.0);
    let p: Placement = "1.7,0,0.2,90,45".parse().unwrap();
    assert!((p.nozzle_spin - std::f64::consts::FRAC_PI_4).abs() < 1e-15);
    assert_eq!(
        Placement::parse("1.7,0,nan,90"),
        Err(PlacementParseError::NotFinite {
            item: 3,
            text: "nan".into()
        })
    );
    assert_eq!(
        Placement::parse("1.7,0,0,inf"),
        Err(PlacementParseError::NotFinite {
            item: 4,
            text: "inf".into()
        })
    );
    assert_eq!(
        Placement::parse("1.7,,0,90"),
        Err(PlacementParseError::Empty { item: 2 })
    );
    assert_eq!(
        Placement::parse("1.7,x,0,90"),
        Err(PlacementParseError::NotANumber {
            item: 2,
            text: "x".into()
        })
    );
    assert_eq!(
        Placement::parse("1.7,0,0"),
        Err(PlacementParseError::Count { got: 3 })
    );
    assert_eq!(
        Placement::parse("1,2,3,4,5,6"),
        Err(PlacementParseError::Count { got: 6 })
    );
    for bad in ["1.7,0,nan,90", "", "1,2", "a,b,c,d"] {
        let msg = Placement::parse(bad).unwrap_err().to_string();
        assert!(!msg.contains("--"), "a library error names a flag: {msg}");
    }
}

fn traj(t: &[f64], q: &[f64]) -> JointTrajectory {
    JointTrajectory {
        n: 1,
        t: t.to_vec(),
        q: q.to_vec(),
        qd: vec![0.0; q.len()],
        qdd: vec![0.0; q.len()],
    }
}

#[test]
fn derivative_completion_keeps_what_the_file_gave() {
    // q = t², q̇ = 2t, q̈ = 2 on a non-uniform grid: the three-point quadratic is exact.
    let t = [0.0, 0.1, 0.25, 0.4, 0.6];
    let q: Vec<f64> = t.iter().map(|x| x * x).collect();
    // Positions only: both derivatives from q.
    let mut a = traj(&t, &q);
    let none = Supplied {
        velocities: false,
        accelerations: false,
    };
    complete_derivatives(&mut a, none).unwrap();
    for (k, &x) in t.iter().enumerate() {
        assert!((a.qd[k] - 2.0 * x).abs() < 1e-12, "{k}");
        assert!((a.qdd[k] - 2.0).abs() < 1e-12, "{k}");
    }
    // Velocities given (deliberately not 2t, to see they are kept): q̈ from them.
    let mut b = traj(&t, &q);
    b.qd = t.iter().map(|x| 3.0 * x).collect();
    let vel = Supplied {
        velocities: true,
        accelerations: false,
    };
    complete_derivatives(&mut b, vel).unwrap();
    for (k, &x) in t.iter().enumerate() {
        assert!((b.qd[k] - 3.0 * x).abs() < 1e-15);
        assert!((b.qdd[k] - 3.0).abs() < 1e-12, "{k}");
    }
    // Accelerations given, velocities not: q̇ from q, q̈ kept.
    let mut c = traj(&t, &q);
    c.qdd = vec![7.0; t.len()];
    let acc = Supplied {
        velocities: false,
        accelerations: true,
    };
    complete_derivatives(&mut c, acc).unwrap();
    assert!(c.qdd.iter().all(|&v| v == 7.0));
    assert!((c.qd[2] - 0.5).abs() < 1e-12);
    // Time not increasing: an error, not a panic, naming no flag.
    let mut d = traj(&[0.0, 0.1, 0.1], &[0.0, 1.0, 2.0]);
    let e = complete_derivatives(&mut d, none).unwrap_err().to_string();
    assert!(
        e.contains("not strictly increasing") && !e.contains("--"),
        "{e}"
    );
}

#[test]
fn train_validation_split_is_the_first_three_quarters_then_the_rest() {
    let (tr, va) = printwatt::identify::train_validation_split(1000);
    assert_eq!((tr, va), (0..750, 750..1000));
    let (tr, va) = printwatt::identify::train_validation_split(7);
    assert_eq!((tr.end, va.start, va.end), (5, 5, 7));
    let (tr, va) = printwatt::identify::train_validation_split(0);
    assert!(tr.is_empty() && va.is_empty());
}

#[test]
fn utc_stamp_names_run_directories() {
    assert_eq!(printwatt::output::utc_stamp(0), "19700101T000000Z");
    assert_eq!(
        printwatt::output::utc_stamp(1_795_000_000),
        "20261118T110640Z"
    );
}
