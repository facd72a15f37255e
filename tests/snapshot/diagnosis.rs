//! Desync diagnosis: `checksum_parts` and `first_difference` name the
//! first differing part, object and field.
use super::*;

#[test]
fn equal_worlds_have_equal_parts_and_no_difference() {
    let w = small_world();
    let c = ok(snapshot::load(&save(&w)));
    assert_eq!(snapshot::first_difference(&w, &c), None);
    let (pa, pb) = (snapshot::checksum_parts(&w), snapshot::checksum_parts(&c));
    assert_eq!(pa, pb);
    assert_eq!(pa.first_mismatch(&pb), None);
    assert_eq!(pa.bodies.len(), w.bodies().count());
    assert_eq!(pa.shapes.len(), w.shapes().count());
}

#[test]
fn first_difference_names_the_body_and_field() {
    let w = small_world();
    let mut c = w.clone();
    let h = nth_body(&c, 2).unwrap_or_else(|| panic!("a body"));
    if let Some(b) = c.body_mut(h) {
        b.set_angular_velocity(b.angular_velocity() + Real::DELTA);
    }
    let d = snapshot::first_difference(&w, &c).unwrap_or_else(|| panic!("a difference"));
    assert_eq!((d.subject, d.field), (Subject::Body(h), "w"));
    assert!(
        d.to_string().contains("body") && d.to_string().contains(" w "),
        "{d}"
    );
    let (pa, pb) = (snapshot::checksum_parts(&w), snapshot::checksum_parts(&c));
    assert_eq!(pa.first_mismatch(&pb), Some(Subject::Body(h)));
    assert_eq!(pa.settings, pb.settings);
    assert_eq!(pa.shapes, pb.shapes);
}

#[test]
fn first_difference_names_settings_shapes_arbiters_and_counters() {
    let w = small_world();
    let mut c = w.clone();
    c.set_iterations(11);
    let d = snapshot::first_difference(&w, &c);
    assert_eq!(
        d.map(|d| (d.subject, d.field)),
        Some((Subject::Settings, "iterations"))
    );

    let mut c = w.clone();
    let s = nth_shape(&c, 1).unwrap_or_else(|| panic!("a shape"));
    ok(c.modify_shape(s, |x| {
        x.collision_type = 9;
        Ok(())
    }));
    let d = snapshot::first_difference(&w, &c);
    assert_eq!(
        d.map(|d| (d.subject, d.field)),
        Some((Subject::Shape(s), "collision_type"))
    );
    let pa = snapshot::checksum_parts(&w);
    assert_eq!(
        pa.first_mismatch(&snapshot::checksum_parts(&c)),
        Some(Subject::Shape(s))
    );

    let mut state = w.state().clone();
    state.arbiters[1].friction += Real::DELTA;
    let c = Space::from_state(state);
    let d = snapshot::first_difference(&w, &c);
    assert_eq!(
        d.map(|d| (d.subject, d.field)),
        Some((Subject::Arbiter(1), "friction"))
    );
    assert_eq!(
        pa.first_mismatch(&snapshot::checksum_parts(&c)),
        Some(Subject::Arbiters)
    );

    let mut state = w.state().clone();
    state.prev_dt += Real::DELTA;
    let c = Space::from_state(state);
    let d = snapshot::first_difference(&w, &c);
    assert_eq!(
        d.map(|d| (d.subject, d.field)),
        Some((Subject::Counters, "prev_dt"))
    );
    assert_eq!(
        pa.first_mismatch(&snapshot::checksum_parts(&c)),
        Some(Subject::Counters)
    );
}

#[test]
fn first_difference_names_presence_and_free_lists() {
    let w = small_world();
    let mut c = w.clone();
    let added = ok(c.add_body(Body::new_static()));
    let d = snapshot::first_difference(&w, &c);
    assert_eq!(
        d.map(|d| (d.subject, d.field)),
        Some((Subject::Body(added), "presence"))
    );

    // Same live bodies, free slots pushed in another order.
    let mut a = w.clone();
    let mut b = w.clone();
    let x = ok(a.add_body(Body::new_static()));
    let y = ok(a.add_body(Body::new_static()));
    assert_eq!(
        (x, y),
        (
            ok(b.add_body(Body::new_static())),
            ok(b.add_body(Body::new_static()))
        )
    );
    ok(a.remove_body(x));
    ok(a.remove_body(y));
    ok(b.remove_body(y));
    ok(b.remove_body(x));
    let d = snapshot::first_difference(&a, &b);
    assert_eq!(d.map(|d| d.subject), Some(Subject::BodyArena));
    let pa = snapshot::checksum_parts(&a);
    assert_eq!(
        pa.first_mismatch(&snapshot::checksum_parts(&b)),
        Some(Subject::BodyArena)
    );
    assert_ne!(a.checksum(), b.checksum());
}

#[test]
fn first_difference_finds_a_desync_after_steps() {
    // The desync workflow: two peers step; one gets a one-ulp different
    // input; the first difference names the body it was applied to.
    let mut a = build("pyramid_20");
    let mut b = build("pyramid_20");
    ok(a.step_n(3));
    ok(b.step_n(3));
    let top = *b.bodies().last().unwrap_or_else(|| panic!("a body"));
    if let Some(body) = b.space.body_mut(top) {
        body.set_velocity(body.velocity() + Vect::new(Real::DELTA, Real::ZERO));
    }
    let d = snapshot::first_difference(&a.space, &b.space).map(|d| d.subject);
    assert_eq!(d, Some(Subject::Body(top)));
    ok(a.step());
    ok(b.step());
    assert_ne!(a.space.checksum(), b.space.checksum());
    assert!(snapshot::first_difference(&a.space, &b.space).is_some());
}
