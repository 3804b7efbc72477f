//! Tests of the regions' exchange: publish, predicted read, restore, the heat flux and the
//! structure temperatures.

use nalgebra::Vector3;

use super::Publication::{Converged, Iterate};
use super::*;

fn loads(x: f64) -> Loads {
    Loads {
        force_n: Vector3::new(x, 2.0 * x, 0.0),
        moment_nm: Vector3::new(0.0, 0.0, -x),
    }
}

fn exchange() -> RegionExchange {
    RegionExchange::new(
        &["left_surface".to_owned()],
        RegionLoadRate::Interval(1e-3),
        RegionLoadRate::Interval(0.01),
        RegionLoadRate::Interval(1e-3),
        0.01,
    )
    .expect("exchange")
}

/// A load linear in time is reproduced exactly at any stage time: the predictor is exact
/// for polynomials of degree one (second-order local error).
#[test]
fn a_load_linear_in_time_is_extrapolated_exactly() {
    let mut h = exchange();
    let f = |t: f64| 3.0 - 7.0 * t;
    for t in [0.0, 1e-3] {
        h.publish_body((t, Converged), &loads(f(t)), &loads(0.5 * f(t)), &[f(t); 2])
            .expect("published");
        h.publish_surface(0, (t, Converged), &loads(-f(t)), &[f(t); 3])
            .expect("published");
    }
    let (mut total, mut aero, mut q) = (Loads::default(), Loads::default(), [0.0; 2]);
    let mut q3 = [0.0; 3];
    for t in [1e-3, 1.5e-3, 2e-3] {
        assert!(h.read_body(t, &mut total, &mut aero, &mut q).expect("read"));
        assert!((total.force_n.x - f(t)).abs() < 1e-12);
        assert!((total.force_n.y - 2.0 * f(t)).abs() < 1e-12);
        assert!((aero.moment_nm.z + 0.5 * f(t)).abs() < 1e-12);
        assert!((q[1] - f(t)).abs() < 1e-12);
        assert!(h.read_surface(0, t, &mut total, &mut q3).expect("read"));
        assert!((total.force_n.x + f(t)).abs() < 1e-12);
        assert!((q3[2] - f(t)).abs() < 1e-12);
    }
    assert_eq!(h.body_time_s(), Some(1e-3));
    assert_eq!(h.surfaces_time_s(), Some(1e-3));
}

/// The friction predictor is exact for a friction linear in time, and steps aside (None)
/// when the friction is due again.
#[test]
fn friction_linear_in_time_is_extrapolated_until_it_is_due() {
    let mut h = exchange();
    let rate = RegionLoadRate::Interval(0.01);
    let f = |t: f64| 2.0 + 5.0 * t;
    assert!(
        h.friction_at(0.0, &rate).expect("read").is_none(),
        "nothing published"
    );
    h.publish_friction(0.0, &loads(f(0.0))).expect("published");
    assert_eq!(
        h.friction_at(0.004, &rate).expect("read"),
        Some(loads(f(0.0))),
        "one: held"
    );
    h.publish_friction(0.01, &loads(f(0.01)))
        .expect("published");
    for t in [0.011, 0.015, 0.019] {
        let read = h.friction_at(t, &rate).expect("read").expect("not due");
        assert!((read.force_n.x - f(t)).abs() < 1e-12);
        assert!((read.moment_nm.z + f(t)).abs() < 1e-12);
    }
    assert!(
        h.friction_at(0.02, &rate).expect("read").is_none(),
        "due at 10 ms"
    );
}

/// The wall heat flux is published every 10 ms and read as published (the latest), and a
/// refresh sooner than its interval is refused naming the topic.
#[test]
fn the_heat_flux_is_held_between_its_refreshes() {
    let mut h = exchange();
    assert_eq!(h.heat_flux(0).expect("read"), None, "none yet");
    assert_eq!(h.heat_flux_time_s(), None);
    h.publish_heat_flux(0, 0.0, &[1.0, 2.0]).expect("published");
    h.publish_heat_flux(0, 0.01, &[3.0, 4.0])
        .expect("published");
    assert_eq!(h.heat_flux(0).expect("read"), Some(&[3.0, 4.0][..]));
    assert_eq!(h.heat_flux_time_s(), Some(0.01));
    let err = h
        .publish_heat_flux(0, 0.015, &[5.0, 6.0])
        .expect_err("sooner than 10 ms");
    assert!(
        err.to_string().contains("left_surface/wall_heat_flux"),
        "{err}"
    );
}

/// One publication is held, none reads nothing, a publication sooner than the declared
/// interval is refused, and clearing forgets everything (a checkpoint round trip restores
/// it).
#[test]
fn one_publication_is_held_none_is_refused_and_clearing_forgets() {
    let mut h = exchange();
    let (mut total, mut aero, mut q) = (Loads::default(), Loads::default(), [0.0; 1]);
    assert!(
        !h.read_body(0.0, &mut total, &mut aero, &mut q)
            .expect("read")
    );
    h.publish_body((0.0, Converged), &loads(4.0), &loads(1.0), &[4.0])
        .expect("published");
    assert!(
        h.read_body(5e-4, &mut total, &mut aero, &mut q)
            .expect("read")
    );
    assert_eq!(total.force_n.x, 4.0);
    assert_eq!(q[0], 4.0);
    let err = h
        .publish_body((5e-4, Converged), &loads(4.0), &loads(1.0), &[4.0])
        .expect_err("sooner than 1 ms");
    assert!(err.to_string().contains("main_body/loads"), "{err}");
    let saved = h.checkpoint();
    h.clear().expect("cleared");
    assert!(
        !h.read_body(0.0, &mut total, &mut aero, &mut q)
            .expect("read")
    );
    h.restore(&saved).expect("restored");
    assert!(
        h.read_body(5e-4, &mut total, &mut aero, &mut q)
            .expect("read")
    );
    assert_eq!(h.checkpoint(), saved);
}

/// Generalized forces published with another length than the reader's buffer are a
/// wiring defect: the read is refused with an error naming the topic and both lengths,
/// and the outputs are left untouched.
#[test]
fn a_publication_of_the_wrong_length_is_refused_naming_the_topic() {
    let mut h = exchange();
    h.publish_body((0.0, Converged), &loads(4.0), &loads(1.0), &[4.0])
        .expect("published");
    let (mut total, mut aero, mut q) = (Loads::default(), Loads::default(), [7.0; 2]);
    let err = h
        .read_body(5e-4, &mut total, &mut aero, &mut q)
        .expect_err("one generalized force published, two read");
    assert_eq!(
        err,
        DataError::LengthMismatch {
            topic: "main_body/loads".to_owned(),
            reader: READER.to_owned(),
            time_s: 5e-4,
            published: 1,
            expected: 2,
        }
    );
    let message = err.to_string();
    for part in ["main_body/loads", "reads 2 entries", "holds 1"] {
        assert!(message.contains(part), "{message}");
    }
    assert_eq!(
        (total, q),
        (Loads::default(), [7.0; 2]),
        "outputs untouched"
    );
    h.publish_surface(0, (0.0, Converged), &loads(1.0), &[1.0; 3])
        .expect("published");
    let err = h
        .read_surface(0, 0.0, &mut total, &mut [0.0; 4])
        .expect_err("three published, four read");
    assert!(err.to_string().contains("left_surface/loads"), "{err}");
}

/// A derivative's evaluation published as an iterate is what the coupling reads at once, but
/// never what the predictor extrapolates: the stages between two accepted states see only the
/// converged publications, and an iterate does not count as the region's last evaluation.
#[test]
fn an_iterate_is_read_at_once_and_never_extrapolated() {
    let mut h = exchange();
    let (mut total, mut aero, mut q) = (Loads::default(), Loads::default(), [0.0; 2]);
    h.publish_body((0.0, Converged), &loads(1.0), &loads(1.0), &[1.0; 2])
        .expect("converged");
    h.publish_body((5e-4, Iterate), &loads(9.0), &loads(8.0), &[9.0; 2])
        .expect("iterate");
    h.read_body_latest(&mut total, &mut aero, &mut q)
        .expect("latest");
    assert_eq!((total, aero, q), (loads(9.0), loads(8.0), [9.0; 2]));
    assert!(
        h.read_body(5e-4, &mut total, &mut aero, &mut q)
            .expect("read")
    );
    assert_eq!(
        (total, q),
        (loads(1.0), [1.0; 2]),
        "held, the iterate unseen"
    );
    assert_eq!(h.body_time_s(), Some(0.0));
    // The next converged publication replaces the iterate; the predictor then uses both.
    h.publish_body((1e-3, Converged), &loads(3.0), &loads(3.0), &[3.0; 2])
        .expect("converged");
    assert!(
        h.read_body(2e-3, &mut total, &mut aero, &mut q)
            .expect("read")
    );
    assert_eq!(total, loads(5.0));
    let mut q3 = [0.0; 3];
    h.publish_surface(0, (1e-3, Iterate), &loads(-2.0), &[2.0; 3])
        .expect("iterate");
    h.read_surface_latest(0, &mut total, &mut q3)
        .expect("latest");
    assert_eq!((total, q3), (loads(-2.0), [2.0; 3]));
    assert!(!h.read_surface(0, 1e-3, &mut total, &mut q3).expect("read"));
    let err = h
        .read_surface_latest(0, &mut total, &mut [0.0; 2])
        .expect_err("two modes read from a three-mode publication");
    assert!(err.to_string().contains("left_surface/loads"), "{err}");
}
