//! The build's parameters: which strategy chooses the planes
//! ([`BuildStrategy`]), the heuristic's costs and limits ([`BuildParams`]),
//! and the measured constants their defaults come from.

use crate::geometry::Primitives;

/// How the build chooses its planes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BuildStrategy {
    /// Surface area heuristic over the clipped objects' bounds, every event
    /// a candidate (Wald & Havran 2006): the default. In scenes of more
    /// than [`BuildParams::bin_past_objects`] objects (2^19) its big nodes
    /// are binned as [`BuildStrategy::Binned`] bins them
    /// ([`BINNED_PAST_OBJECTS`] says why).
    #[default]
    Sah,
    /// The same heuristic evaluated at 32 bin boundaries per axis, snapped
    /// to the nearest object faces, in nodes of many objects, exact below
    /// (after Shevtsov et al. 2007): a tree as good by the heuristic (within
    /// 1-3%) and as fast to trace, built 1.3-1.5x faster (docs/benchmarks.md).
    Binned,
    /// The seed study's Algorithm 2: the median of the objects' centres on
    /// axis `depth mod 3`, down to one object per leaf, with straddling
    /// objects in both children (the study put them on one side only).
    Median,
}

impl BuildStrategy {
    pub const ALL: [BuildStrategy; 3] = [
        BuildStrategy::Sah,
        BuildStrategy::Binned,
        BuildStrategy::Median,
    ];

    /// The next strategy of [`BuildStrategy::ALL`], round (the window's K).
    pub fn next(self) -> BuildStrategy {
        let i = BuildStrategy::ALL
            .iter()
            .position(|&b| b == self)
            .unwrap_or(0);
        BuildStrategy::ALL[(i + 1) % BuildStrategy::ALL.len()]
    }

    pub fn name(self) -> &'static str {
        match self {
            BuildStrategy::Sah => "sah",
            BuildStrategy::Binned => "binned",
            BuildStrategy::Median => "median",
        }
    }
}

impl std::fmt::Display for BuildStrategy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl crate::choice::Choice for BuildStrategy {
    const ALL: &'static [Self] = &BuildStrategy::ALL;

    fn name(self) -> &'static str {
        BuildStrategy::name(self)
    }

    fn help(self) -> &'static str {
        match self {
            BuildStrategy::Sah => "surface area heuristic with perfect splits, every event a candidate (Wald & Havran 2006); binned in big nodes past 2^19 objects",
            BuildStrategy::Binned => "the same, binned in big nodes with snapped boundaries: a faster build of a tree as good",
            BuildStrategy::Median => "the seed's median split, straddlers in both children",
        }
    }
}

/// Knobs of the build. Costs are in units of one traversal step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BuildParams {
    pub max_depth: u32,
    pub traversal_cost: f32,
    pub intersection_cost: f32,
    /// Cost factor (< 1) that rewards cutting off empty space.
    pub empty_bonus: f32,
    /// The binned build ([`BuildStrategy::Binned`]) bins nodes of more
    /// objects than this and sweeps every event of the others.
    pub exact_below: usize,
    /// The default build ([`BuildStrategy::Sah`]) bins as the binned build
    /// does in scenes of more objects than this ([`BINNED_PAST_OBJECTS`]),
    /// and sweeps every event of every node in the others.
    pub bin_past_objects: usize,
    pub strategy: BuildStrategy,
}

/// The cost of testing a sphere, in the build's units (a traversal step
/// costs 40): Wald & Havran's 20 (see [`BuildParams::for_object_count`]).
pub const SPHERE_TEST_COST: f32 = 20.0;

/// The cost of testing a triangle in a scene of `objects` objects: 80 (four
/// sphere tests) up to [`SMALL_SCENE_OBJECTS`], 40 up to
/// [`LARGE_SCENE_OBJECTS`], 10 ([`LARGE_SCENE_TRIANGLE_COST`]) beyond. A
/// triangle test loads nine floats where a sphere's loads four, and the
/// frame of a mesh is faster the more the heuristic trades its triangle
/// tests for node steps; but the tree grows with it (about 11, 6, 2 and 0.7
/// nodes a triangle on the bunny), and with it the build and the GPU arrays.
/// Measured on lavapipe (docs/design.md "Costs"): at 80 against 40 the
/// bunny, the torus and `scenes/bunny.toml` render 7 - 8% faster and the
/// gears 2.5%; at 40 against 20, 6 - 18% on meshes up to 1.1 M triangles.
/// Past the tiers the build costs more than one 1080p frame gains: at
/// 278,664 triangles 80 builds in 1.61 s instead of 1.13 for a 7% faster
/// frame; past 2^19 the cost is a trade of the frame for the build, no
/// longer a test's price: at 1.1 M triangles 10 builds in 0.95 s instead of
/// 1.49 (binned) with 37% smaller GPU arrays, for a frame 7% slower (3.75
/// against 3.52 s at 1080p), and build + upload + frame is 8% shorter; at
/// 557,332 triangles 2% shorter.
pub fn triangle_test_cost(objects: usize) -> f32 {
    if objects <= SMALL_SCENE_OBJECTS {
        80.0
    } else if objects <= LARGE_SCENE_OBJECTS {
        40.0
    } else {
        LARGE_SCENE_TRIANGLE_COST
    }
}

/// A triangle's cost past [`LARGE_SCENE_OBJECTS`] ([`triangle_test_cost`]).
/// Not what a test costs (about twice a sphere's) but the build's price:
/// leaves of about 7 triangles instead of 3, a third of the nodes, for a
/// frame 6 - 7% slower (docs/design.md "A fourth tier").
pub const LARGE_SCENE_TRIANGLE_COST: f32 = 10.0;

/// Scenes of at most this many objects test a triangle at 80
/// ([`triangle_test_cost`]).
pub const SMALL_SCENE_OBJECTS: usize = 1 << 17;

/// Scenes of more than this many objects test a triangle at
/// [`LARGE_SCENE_TRIANGLE_COST`] ([`triangle_test_cost`]).
pub const LARGE_SCENE_OBJECTS: usize = 1 << 19;

/// The factor (< 1) on the cost of a split that leaves one child empty:
/// 0.95, where Wald & Havran 2006 took 0.8. Measured on lavapipe (docs/
/// design.md "Costs"): the gears' frame 11% faster (502 - 505
/// against 562 - 599 ms), the 1.1 M bunny built 4% faster with 13% fewer
/// nodes, the bunny, the torus and random spheres within 1%, a random
/// triangle soup 3% slower. With the weaker bonus the gears' tree spends
/// its splits on separating the thin triangles rather than on cutting off
/// empty space: 24,913 nodes instead of 14,371, and 7.2 triangles tested a
/// ray instead of 9.2.
pub const EMPTY_BONUS: f32 = 0.95;

impl BuildParams {
    /// Depth limit 8 + 1.3 log2 N (Havran's rule of thumb); intersection
    /// cost 20 ([`SPHERE_TEST_COST`]) as in Wald & Havran 2006, but
    /// traversal 40 rather than their 15: kd-restart re-descends for every
    /// leaf, so steps cost more than in a stack walk.
    /// Measured on lavapipe (see docs/benchmarks.md): 11-18% faster at
    /// 1,000 to 1,000,000 spheres, and less than half the tree memory at a
    /// million. With the rope walk and 8-byte nodes, a million spheres are
    /// still fastest at 40 (20 is 5% slower there, 1-5% faster at 1,000 and
    /// 10,000). Empty bonus 0.95 ([`EMPTY_BONUS`]) rather than their 0.8.
    pub fn for_object_count(n: usize) -> Self {
        let max_depth = (8.0 + 1.3 * (n.max(1) as f64).log2()).round() as u32;
        BuildParams {
            max_depth: max_depth.min(64),
            traversal_cost: 40.0,
            intersection_cost: SPHERE_TEST_COST,
            empty_bonus: EMPTY_BONUS,
            exact_below: BINNED_EXACT_BELOW,
            bin_past_objects: BINNED_PAST_OBJECTS,
            strategy: BuildStrategy::Sah,
        }
    }

    /// Nodes of more objects than this are split by binning, the others by
    /// the exact sweep, in a scene of `objects` objects: `exact_below` for
    /// the binned build at every size and for the default one past
    /// `bin_past_objects`; never otherwise.
    pub fn binned_above(&self, objects: usize) -> usize {
        match self.strategy {
            BuildStrategy::Binned => self.exact_below,
            BuildStrategy::Sah if objects > self.bin_past_objects => self.exact_below,
            BuildStrategy::Sah | BuildStrategy::Median => usize::MAX,
        }
    }

    /// The defaults for a scene's objects: the intersection cost is the
    /// mean of its objects' test costs ([`SPHERE_TEST_COST`],
    /// [`triangle_test_cost`]), since the heuristic counts objects, not
    /// their kinds.
    pub fn for_primitives(prims: &Primitives) -> Self {
        let n = prims.len();
        let mut params = Self::for_object_count(n);
        if n > 0 {
            let spheres = prims.spheres.len() as f64;
            let triangles = prims.triangles.len() as f64;
            let total =
                spheres * SPHERE_TEST_COST as f64 + triangles * triangle_test_cost(n) as f64;
            params.intersection_cost = (total / n as f64) as f32;
        }
        params
    }
}

/// With [`BuildStrategy::Binned`], nodes of more objects than this are
/// split by binning (see [`BuildParams::exact_below`]). Measured on the
/// bunny subdivided to 1.1 M triangles, one thread, CPU time under load 3
/// (two runs each): 8 built in 4.8-4.9 s but with
/// 8% more references, 32 in 5.0-5.4 s, 128 and 512 in 6.1-7.4 s, the
/// exact sweep everywhere in 7.3-7.8 s; 32 is the compromise. With snapped
/// bins, 12 and 6 gave
/// 2% and 4% more nodes and built no faster than 32. With leaves of about
/// 7 triangles (`LARGE_SCENE_TRIANGLE_COST`) and the search without sorting
/// up to 16 objects, 16 builds the 1.1 M bunny in 1.69 s of one thread
/// against 1.77 s at 32 (three rounds each), with 1% more
/// references, the same heuristic cost (200.5), the same image, nodes
/// visited (12.87 a ray against 12.86) and objects tested (8.51) and a
/// frame within the noise; on smaller scenes 0.2 - 1% more references
/// and a cost within 0.1%.
pub const BINNED_EXACT_BELOW: usize = 16;

/// The default build ([`BuildStrategy::Sah`]) bins the big nodes of scenes
/// of more objects than this ([`BuildParams::bin_past_objects`]): the size
/// past which a triangle's cost is the build's price, not a test's
/// ([`LARGE_SCENE_OBJECTS`]). Measured past it (two threads,
/// docs/benchmarks.md): the exact sweep built the 1.1 M bunny in 3.2 s
/// against 1.5 s binned and two 278 k bunnies in 1.64 s against 0.72 s,
/// for trees within 1% by the heuristic; the 1.1 M bunny's image was the
/// same, byte for byte, and its frame the same. Up to it every tree stays
/// the exact sweep's.
pub const BINNED_PAST_OBJECTS: usize = LARGE_SCENE_OBJECTS;

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// A scene's intersection cost is the mean of its objects' test costs.
    #[test]
    fn intersection_cost_follows_the_scene_kinds() {
        use crate::geometry::{SphereF32, TriangleF32};
        let sphere = SphereF32 {
            center: Vec3::ZERO,
            radius: 1.0,
        };
        let triangle = TriangleF32 {
            v: [Vec3::ZERO, Vec3::X, Vec3::Y],
        };
        let scene = |s: usize, t: usize| Primitives {
            spheres: vec![sphere; s],
            triangles: vec![triangle; t],
            alpha: None,
        };
        let cost = |s, t| BuildParams::for_primitives(&scene(s, t)).intersection_cost;
        assert_eq!(cost(0, 0), SPHERE_TEST_COST);
        assert_eq!(cost(5, 0), SPHERE_TEST_COST);
        assert_eq!(cost(0, 5), 80.0);
        assert_eq!(cost(1, 3), (SPHERE_TEST_COST + 3.0 * 80.0) / 4.0);
        let params = BuildParams::for_primitives(&scene(1, 3));
        assert_eq!(params.traversal_cost, 40.0);
        // The tiers, at their edges.
        assert_eq!(cost(0, SMALL_SCENE_OBJECTS), 80.0);
        assert_eq!(cost(0, SMALL_SCENE_OBJECTS + 1), 40.0);
        assert_eq!(cost(0, LARGE_SCENE_OBJECTS), 40.0);
        assert_eq!(cost(0, LARGE_SCENE_OBJECTS + 1), LARGE_SCENE_TRIANGLE_COST);
    }

    /// The default build sweeps every event up to `bin_past_objects`
    /// objects and bins beyond, at the binned build's `exact_below`; the
    /// binned build bins at every size, the median build never.
    #[test]
    fn the_default_build_bins_only_past_its_scene_size() {
        let params = |strategy| BuildParams {
            strategy,
            ..BuildParams::for_object_count(10)
        };
        let sah = params(BuildStrategy::Sah);
        assert_eq!(sah.bin_past_objects, BINNED_PAST_OBJECTS);
        assert_eq!(BINNED_PAST_OBJECTS, LARGE_SCENE_OBJECTS);
        assert_eq!(sah.binned_above(BINNED_PAST_OBJECTS), usize::MAX);
        assert_eq!(
            sah.binned_above(BINNED_PAST_OBJECTS + 1),
            BINNED_EXACT_BELOW
        );
        for n in [0, 17, BINNED_PAST_OBJECTS + 1] {
            assert_eq!(
                params(BuildStrategy::Binned).binned_above(n),
                BINNED_EXACT_BELOW
            );
            assert_eq!(params(BuildStrategy::Median).binned_above(n), usize::MAX);
        }
    }
}
