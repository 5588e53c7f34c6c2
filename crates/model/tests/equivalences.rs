//! The parameter sets that give the same BRDF (docs/model.md, "Equivalent parameter sets"), and
//! the direction of the pan rotation, checked by evaluating every registered family at both
//! parametrisations on random directions. A fit printed in another of these forms is the same
//! fit (issue 45.23), and `Layout::equivalence_note` says so; these tests keep the docs true.

use brdf_model::{FamilyRef, LobeKind, Params, Role, family, family_names, uniform_hemisphere};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;

/// Random direction pairs on the upper hemisphere.
fn pairs(seed: u64) -> Vec<([f64; 3], [f64; 3])> {
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    (0..400)
        .map(|_| (uniform_hemisphere(&mut rng), uniform_hemisphere(&mut rng)))
        .collect()
}

/// The family's anisotropic x/y pair (the fields an isotropic lobe ties) and its pan field,
/// when it has both.
fn pair_and_pan(f: &FamilyRef) -> Option<(usize, usize, usize)> {
    let tied = f
        .lobe_params(LobeKind::Isotropic)?
        .iter()
        .find(|d| d.fields.len() == 2)?;
    let pan = f
        .lobe_params(LobeKind::Anisotropic)?
        .iter()
        .find(|d| d.role == Role::Angle)?;
    Some((tied.fields[0], tied.fields[1], pan.fields[0]))
}

/// A random lobe of `f` inside its box, with shape parameters kept moderate (an exponent of
/// 10,000 would make almost every value 0 and the comparison empty).
fn random_lobe(f: &FamilyRef, rng: &mut Pcg64Mcg) -> Vec<f64> {
    f.lobe_fields()
        .iter()
        .map(|field| {
            let (lo, hi) = field.bounds;
            let hi = if hi - lo > 10.0 { lo + 40.0 } else { hi };
            lo + (hi - lo) * rng.random::<f64>()
        })
        .collect()
}

/// `a` and `b` agree at every direction pair (relative 1e-9: the pan's sine and cosine are
/// rounded differently at different angles).
fn assert_same(a: &Params, b: &Params, what: &str) {
    let mut nonzero = 0;
    for (u, v) in pairs(7) {
        let (x, y) = (a.value(u, v), b.value(u, v));
        assert!(
            (x - y).abs() <= 1e-9 * x.abs().max(y.abs()) + 1e-300,
            "{} {what}: {x} vs {y} at u={u:?} v={v:?}",
            a.family().name()
        );
        nonzero += usize::from(x != 0.0);
    }
    assert!(nonzero > 20, "{what}: too few nonzero values to compare");
}

/// Families with an anisotropic x/y pair and a pan.
fn panned() -> Vec<(FamilyRef, (usize, usize, usize))> {
    let out: Vec<_> = family_names()
        .into_iter()
        .map(|n| family(n).unwrap())
        .filter_map(|f| pair_and_pan(&f).map(|p| (f, p)))
        .collect();
    assert!(out.iter().any(|(f, _)| f.name() == "lafortune"));
    out
}

fn params(f: &FamilyRef, lobes: Vec<Vec<f64>>) -> Params {
    // No constant term: the lobes alone are compared.
    let shared = f.shared_fields().iter().map(|_| 0.0).collect();
    Params::new(f.clone(), shared, lobes).unwrap()
}

/// `(x, y, pan)` and `(y, x, pan + 90)` are one lobe: turning the frame by 90 degrees makes
/// the old y axis the new x axis (and the old x axis the new -y, which the lobes see squared
/// or as a product of two components).
#[test]
fn pan_plus_90_with_x_and_y_swapped_is_the_same_lobe() {
    let mut rng = Pcg64Mcg::seed_from_u64(1);
    for (f, (x, y, pan)) in panned() {
        for _ in 0..20 {
            let mut a = random_lobe(&f, &mut rng);
            a[pan] = -90.0 + 90.0 * rng.random::<f64>();
            let mut b = a.clone();
            b.swap(x, y);
            b[pan] = a[pan] + 90.0;
            assert_same(
                &params(&f, vec![a]),
                &params(&f, vec![b]),
                "pan + 90, x/y swapped",
            );
        }
    }
}

/// Pan -90 and pan 90 (the box's ends) are one angle: a turn by 180 degrees flips both axes.
#[test]
fn pan_minus_90_and_90_are_the_same_lobe() {
    let mut rng = Pcg64Mcg::seed_from_u64(2);
    for (f, (_, _, pan)) in panned() {
        for _ in 0..20 {
            let mut a = random_lobe(&f, &mut rng);
            a[pan] = -90.0;
            let mut b = a.clone();
            b[pan] = 90.0;
            assert_same(&params(&f, vec![a]), &params(&f, vec![b]), "pan -90 vs 90");
        }
    }
}

/// With equal x and y parameters the pan has no effect (an isotropic lobe).
#[test]
fn equal_x_and_y_make_the_pan_irrelevant() {
    let mut rng = Pcg64Mcg::seed_from_u64(3);
    for (f, (x, y, pan)) in panned() {
        let mut a = random_lobe(&f, &mut rng);
        a[y] = a[x];
        a[pan] = 0.0;
        let mut b = a.clone();
        b[pan] = -90.0 + 180.0 * rng.random::<f64>();
        assert_same(&params(&f, vec![a]), &params(&f, vec![b]), "x = y, any pan");
    }
}

/// The lobes are summed, so their order is free.
#[test]
fn lobes_in_another_order_are_the_same_brdf() {
    let mut rng = Pcg64Mcg::seed_from_u64(4);
    for name in family_names() {
        let f = family(name).unwrap();
        let (a, b) = (random_lobe(&f, &mut rng), random_lobe(&f, &mut rng));
        assert_same(
            &params(&f, vec![a.clone(), b.clone()]),
            &params(&f, vec![b, a]),
            "lobes swapped",
        );
    }
}

/// The direction of the pan: a positive pan turns the lobe's axes counter-clockwise about the
/// normal seen from above (from +z, x towards y). So a lobe turned by +phi, evaluated at
/// directions turned by +phi the same way, is the unturned lobe at the unturned directions.
#[test]
fn a_positive_pan_turns_the_lobe_counter_clockwise_seen_from_above() {
    let turn = |w: [f64; 3], deg: f64| {
        let (s, c) = deg.to_radians().sin_cos();
        [c * w[0] - s * w[1], s * w[0] + c * w[1], w[2]]
    };
    let mut rng = Pcg64Mcg::seed_from_u64(5);
    for (f, (x, y, pan)) in panned() {
        let mut lobe = random_lobe(&f, &mut rng);
        // Clearly anisotropic, so that a turn the other way would show: a tenth and half of
        // the pair's (moderate) range, or for Lafortune a forward lobe stretched along y.
        if f.name() == "lafortune" {
            lobe[..4].copy_from_slice(&[-0.3, -1.0, 1.0, 5.0]);
        } else {
            let (lo, hi) = f.lobe_fields()[x].bounds;
            let span = (hi - lo).min(40.0);
            lobe[x] = lo + 0.1 * span;
            lobe[y] = lo + 0.5 * span;
        }
        lobe[pan] = 0.0;
        let unturned = params(&f, vec![lobe.clone()]);
        for phi in [30.0, 55.0, -70.0] {
            let mut turned = lobe.clone();
            turned[pan] = phi;
            let turned = params(&f, vec![turned]);
            let mut wrong = 0;
            for (u, v) in pairs(8) {
                let want = unturned.value(u, v);
                let got = turned.value(turn(u, phi), turn(v, phi));
                assert!(
                    (want - got).abs() <= 1e-9 * want.abs().max(got.abs()) + 1e-300,
                    "{}: pan {phi}: {got} vs {want}",
                    f.name()
                );
                let other = turned.value(turn(u, -phi), turn(v, -phi));
                wrong += usize::from((other - want).abs() > 1e-6 * want.abs());
            }
            assert!(wrong > 20, "{}: the opposite turn should differ", f.name());
        }
    }
}

/// The note printed beside a fit names exactly the forms a layout has.
#[test]
fn the_note_names_the_forms_the_layout_has() {
    use brdf_model::Layout;
    let note = |kinds: &[LobeKind]| Layout::builder(kinds).build().unwrap().equivalence_note();
    assert_eq!(note(&[LobeKind::Isotropic]), None);
    let one = note(&[LobeKind::Anisotropic]).unwrap();
    assert!(
        one.contains("pan + or - 90") && !one.contains("order"),
        "{one}"
    );
    assert!(one.contains("docs/model.md"), "{one}");
    let two = note(&[LobeKind::Isotropic, LobeKind::Isotropic]).unwrap();
    assert!(
        two.contains("another order") && !two.contains("pan"),
        "{two}"
    );
}
