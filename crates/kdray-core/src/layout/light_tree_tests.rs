//! The light tree against its definition: probabilities that sum to one
//! and equal the walk's, at random points with and without a normal.

use super::*;

/// A small deterministic generator (splitmix64) of numbers in [0, 1).
struct Numbers(u64);

impl Numbers {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        (z ^ (z >> 31)) as f64 / 2f64.powi(64)
    }

    fn point(&mut self, scale: f64) -> Vec3 {
        let v = [0; 3].map(|_| (2.0 * self.next() - 1.0) * scale);
        DVec3::from(v).as_vec3()
    }
}

/// Every kind of emitter the tree holds: spheres, one-sided and
/// two-sided triangles of random sizes, places and orientations, and
/// one of no power, which it leaves out; with each its points (a
/// sphere's centre and radius, a triangle's corners).
fn emitters_with_points(count: usize, seed: u64) -> Vec<(u32, LightBounds, Vec<Vec3>)> {
    let mut n = Numbers(seed);
    let mut out: Vec<(u32, LightBounds, Vec<Vec3>)> = (0..count)
        .map(|i| {
            let at = n.point(4.0);
            let phi = 0.01 + 10.0 * n.next().powi(3);
            let (b, points) = match i % 3 {
                0 => {
                    let r = 0.05 + 0.3 * n.next() as f32;
                    (LightBounds::sphere(at, r, phi), vec![at, Vec3::splat(r)])
                }
                k => {
                    let size = 0.05 + 0.5 * n.next();
                    let v = [at, at + n.point(size), at + n.point(size)];
                    (LightBounds::triangle(v, phi, k == 2), v.to_vec())
                }
            };
            (1000 - i as u32, b, points)
        })
        .collect();
    out[count / 2].1.phi = 0.0;
    out
}

fn emitters(count: usize, seed: u64) -> Vec<(u32, LightBounds)> {
    emitters_with_points(count, seed)
        .into_iter()
        .map(|(k, b, _)| (k, b))
        .collect()
}

/// At random shading points, the probabilities of the walk ending at
/// each emitter sum to one, less the chance of a dead end (an inner
/// node whose bounds promise light its children do not have: the walk
/// then picks nothing); each is what the walk reports when it ends
/// there; and the walk's frequencies follow them.
#[test]
fn the_trees_pick_probabilities_sum_to_one_and_are_the_walks() {
    let emitters = emitters(60, 7);
    let tree = LightTree::build(&emitters);
    assert_eq!(
        tree.nodes.len(),
        2 * 59 - 1,
        "one leaf per emitter with power"
    );
    assert_eq!(tree.leaf_of[30], NO_LEAF);
    let mut n = Numbers(11);
    let mut whole = 0;
    for _ in 0..20 {
        let p = n.point(6.0).as_dvec3();
        let normal = match n.next() < 0.5 {
            true => DVec3::ZERO,
            false => n.point(1.0).as_dvec3().normalize(),
        };
        let pmf: Vec<f64> = (0..emitters.len())
            .map(|e| tree.pmf(p, normal, e))
            .collect();
        let sum: f64 = pmf.iter().sum();
        assert_eq!(pmf[30], 0.0, "an emitter of no power is never picked");
        let draws = 20_000;
        let mut counts = vec![0u32; emitters.len() + 1];
        for k in 0..draws {
            let u = (k as f64 + n.next()) / draws as f64;
            let Some((e, probability)) = tree.sample(p, normal, u) else {
                counts[emitters.len()] += 1;
                continue;
            };
            let want = pmf[e];
            assert!(
                (probability - want).abs() <= 1e-12 * want,
                "at {p}: emitter {e} picked with {probability}, its pmf is {want}"
            );
            counts[e] += 1;
        }
        let dead_end = 1.0 - sum;
        assert!(dead_end > -1e-9, "at {p}: the picks sum to {sum}");
        whole += usize::from(dead_end.abs() < 1e-9);
        for (e, &c) in counts.iter().enumerate() {
            let want = pmf.get(e).copied().unwrap_or(dead_end.max(0.0));
            let f = c as f64 / draws as f64;
            let sigma = (want * (1.0 - want) / draws as f64).sqrt();
            assert!(
                (f - want).abs() <= 5.0 * sigma + 1e-4,
                "at {p}: emitter {e} (or none) drawn {f}, its chance {want}"
            );
        }
    }
    assert!(whole >= 5, "some points have no dead end: {whole} of 20");
}

/// An emitter that sends light toward p, from a part of it in front of
/// the surface at p, has a chance of being picked there (else the
/// estimate would miss its light); one-sided triangles seen from
/// behind, and emitters behind the surface, mostly have none.
#[test]
fn every_emitter_that_lights_a_point_can_be_picked_there() {
    let emitters = emitters_with_points(45, 3);
    let tree = LightTree::build(
        &emitters
            .iter()
            .map(|(k, b, _)| (*k, *b))
            .collect::<Vec<_>>(),
    );
    let mut n = Numbers(5);
    let (mut lit, mut behind, mut below) = (0, 0, 0);
    for k in 0..400 {
        let p = n.point(6.0).as_dvec3();
        let normal = match k % 2 {
            0 => DVec3::ZERO,
            _ => n.point(1.0).as_dvec3().normalize(),
        };
        // How far a point lies in front of the surface at p.
        let height = |q: DVec3| match normal == DVec3::ZERO {
            true => 1.0,
            false => normal.dot(q - p),
        };
        for (e, (_, b, points)) in emitters.iter().enumerate() {
            if b.phi <= 0.0 {
                continue;
            }
            let pmf = tree.pmf(p, normal, e);
            if b.cos_theta_o < 0.0 {
                let (c, r) = (points[0].as_dvec3(), points[1].x as f64);
                if (p - c).length() > r && height(c) > -r + 1e-6 {
                    assert!(pmf > 0.0, "sphere {e} lights {p} but is never picked");
                    lit += 1;
                } else if height(c) < -r && pmf == 0.0 {
                    below += 1;
                }
                continue;
            }
            // The side of each corner p lies on (the plane's, all alike
            // but for rounding).
            let sides: Vec<f64> = points
                .iter()
                .map(|q| b.axis.dot(p - q.as_dvec3()))
                .collect();
            let front = sides.iter().all(|&c| c > 1e-6);
            let back = sides.iter().all(|&c| c < -1e-6);
            let above = points.iter().any(|q| height(q.as_dvec3()) > 1e-6);
            if (front || (b.two_sided && back)) && above {
                assert!(pmf > 0.0, "triangle {e} lights {p} but is never picked");
                lit += 1;
            } else if back && pmf == 0.0 {
                behind += 1;
            } else if !above && pmf == 0.0 {
                below += 1;
            }
        }
    }
    // The bounds are loose near a plane, tight far behind it.
    assert!(
        lit > 1000 && behind > 500 && below > 500,
        "lit {lit}, pruned behind {behind}, below the surface {below}"
    );
}

/// The tree depends on the emitters and their keys, not their order.
#[test]
fn the_same_emitters_in_another_order_give_the_same_tree() {
    let emitters = emitters(40, 9);
    let tree = LightTree::build(&emitters);
    let mut reversed = emitters.clone();
    reversed.reverse();
    let other = LightTree::build(&reversed);
    let last = emitters.len() - 1;
    let map = |n: &GpuLightNode| match n.is_leaf() {
        true => GpuLightNode {
            child: LIGHT_TREE_LEAF | (last as u32 - (n.child & !LIGHT_TREE_LEAF)),
            ..*n
        },
        false => *n,
    };
    assert_eq!(tree.nodes, other.nodes.iter().map(map).collect::<Vec<_>>());
}

/// A node goes into a lights-buffer record and back unchanged.
#[test]
fn a_node_survives_its_lights_buffer_record() {
    let tree = LightTree::build(&emitters(9, 1));
    for n in &tree.nodes {
        assert_eq!(GpuLightNode::from_light(&n.to_light()), *n);
    }
    // Each inner node bounds its children's boxes and has their power.
    for n in tree.nodes.iter().filter(|n| !n.is_leaf()) {
        let [a, b] = [0, 1].map(|k| tree.nodes[n.child as usize + k]);
        assert!((n.phi - (a.phi + b.phi)).abs() <= 1e-5 * n.phi);
        for c in [a, b] {
            assert!((0..3).all(|i| n.lo[i] <= c.lo[i] && c.hi[i] <= n.hi[i]));
        }
    }
    // Each emitter's cone of normals lies in each of its ancestors'.
    let angle = |x: f32| (x as f64).clamp(-1.0, 1.0).acos();
    for leaf in tree.nodes.iter().filter(|n| n.is_leaf()) {
        let mut up = leaf.parent;
        while up != LIGHT_TREE_ROOT {
            let n = &tree.nodes[up as usize];
            let between = Vec3::from(n.axis)
                .as_dvec3()
                .dot(Vec3::from(leaf.axis).as_dvec3())
                .clamp(-1.0, 1.0)
                .acos();
            assert!(
                between + angle(leaf.cos_theta_o) <= angle(n.cos_theta_o) + 1e-3,
                "{leaf:?} in {n:?}"
            );
            up = n.parent;
        }
    }
}

/// Reweighting the leaves changes the picks to follow the new powers
/// and keeps them summing to one.
#[test]
fn reweighted_leaves_give_picks_by_their_new_powers() {
    let emitters = emitters(12, 4);
    let mut tree = LightTree::build(&emitters);
    LightTree::reweight(&mut tree.nodes, |e| if e == 2 { 1e6 } else { 1.0 });
    let p = DVec3::new(0.3, 9.0, -0.2);
    let sum: f64 = (0..emitters.len())
        .map(|e| tree.pmf(p, DVec3::ZERO, e))
        .sum();
    assert!((sum - 1.0).abs() < 1e-9);
    let pick = tree.pmf(p, DVec3::ZERO, 2);
    assert!(pick > 0.9, "{pick}");
}
