//! Deterministic random scenes for `kdray bench` and `kdray generate`, and a
//! writer for any [`Scene`] as a scene file (TOML or JSON).
//!
//! The generator owns its PRNG (SplitMix64, a dozen lines) so that a seed
//! gives the same scene on every platform and in every version of kdray's
//! dependencies. Every coordinate is rounded to 6 decimals before it enters
//! the scene, so a written file reads back as exactly the same `Scene`.
//!
//! Layout: `count` objects with centres uniform in the box [-2, 2]^3, seen by
//! a camera at (0, 1.5, 8.5) looking at the origin. Object sizes shrink as
//! `c / cbrt(N)`, which keeps the fraction of the box they fill constant
//! (about 0.75% for spheres), so the picture stays a cloud of distinct
//! objects at every N. One white light; a quarter of the objects are half
//! mirrors.

use std::fmt::Write as _;

use glam::DVec3;

use crate::scene::{
    Camera, Light, Material, RenderSettings, Scene, SceneFormat, ShadowMode, Sphere, Triangle,
};

/// What the random objects are.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SceneKind {
    /// Spheres only.
    Spheres,
    /// Triangles only.
    Triangles,
    /// Half spheres (rounded up), half triangles.
    Mixed,
    /// Gear wheels whose flat faces are 144-vertex polygons fan-triangulated
    /// into long thin triangles, with quad rims, on a floor (see [`gears`]).
    Gears,
}

impl SceneKind {
    pub fn name(self) -> &'static str {
        match self {
            SceneKind::Spheres => "spheres",
            SceneKind::Triangles => "triangles",
            SceneKind::Mixed => "mixed",
            SceneKind::Gears => "gears",
        }
    }
}

impl crate::choice::Choice for SceneKind {
    const ALL: &'static [Self] = &[Self::Spheres, Self::Triangles, Self::Mixed, Self::Gears];

    fn name(self) -> &'static str {
        SceneKind::name(self)
    }

    fn help(self) -> &'static str {
        match self {
            Self::Spheres => "spheres only",
            Self::Triangles => "triangles only",
            Self::Mixed => "half spheres (rounded up), half triangles",
            Self::Gears => "gear wheels of long thin triangles (144-vertex faces, fanned)",
        }
    }
}

/// The default seed of `kdray bench` and `kdray generate`.
pub const DEFAULT_SEED: u64 = 20_261_121;
/// Half the side of the box the objects' centres are drawn in.
pub const BOX_HALF: f64 = 2.0;
/// Mean sphere radius is `SPHERE_SCALE / cbrt(N)`.
pub const SPHERE_SCALE: f64 = 0.45;
/// Mean triangle "radius" (centre to vertex) is `TRIANGLE_SCALE / cbrt(N)`.
pub const TRIANGLE_SCALE: f64 = 0.7;
/// Default image size of the random scenes.
pub const DEFAULT_WIDTH: u32 = 640;
pub const DEFAULT_HEIGHT: u32 = 480;

/// SplitMix64 (Steele, Lea and Flood 2014): tiny, fast, and good enough to
/// scatter objects; fixed here so scenes never change with a crate update.
#[derive(Debug, Clone)]
pub struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    pub fn new(seed: u64) -> Self {
        SplitMix64 { state: seed }
    }

    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1), 53 random bits.
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_f64()
    }

    /// Uniform in 0..n (n > 0); the modulo bias is far below what matters here.
    pub fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n
    }

    /// A uniformly distributed unit vector.
    pub fn unit_vector(&mut self) -> DVec3 {
        let z = self.range(-1.0, 1.0);
        let phi = self.range(0.0, std::f64::consts::TAU);
        let s = (1.0 - z * z).max(0.0).sqrt();
        DVec3::new(s * phi.cos(), s * phi.sin(), z)
    }
}

/// Rounds to 6 decimals, so the value prints short and reads back exactly.
fn q(x: f64) -> f64 {
    (x * 1e6).round() / 1e6
}

fn qv(v: DVec3) -> DVec3 {
    DVec3::new(q(v.x), q(v.y), q(v.z))
}

/// What to generate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RandomSceneSpec {
    pub kind: SceneKind,
    pub count: usize,
    pub seed: u64,
    pub width: u32,
    pub height: u32,
}

impl RandomSceneSpec {
    pub fn new(kind: SceneKind, count: usize) -> Self {
        RandomSceneSpec {
            kind,
            count,
            seed: DEFAULT_SEED,
            width: DEFAULT_WIDTH,
            height: DEFAULT_HEIGHT,
        }
    }

    /// Spheres and triangles this spec produces.
    pub fn split(&self) -> (usize, usize) {
        match self.kind {
            SceneKind::Spheres => (self.count, 0),
            SceneKind::Triangles | SceneKind::Gears => (0, self.count),
            SceneKind::Mixed => (self.count.div_ceil(2), self.count / 2),
        }
    }
}

/// (name, diffuse colour) of the palette; each colour comes matte and shiny.
const PALETTE: [(&str, [f64; 3]); 6] = [
    ("red", [0.8, 0.15, 0.1]),
    ("orange", [0.9, 0.5, 0.1]),
    ("yellow", [0.85, 0.8, 0.2]),
    ("green", [0.2, 0.7, 0.25]),
    ("blue", [0.15, 0.3, 0.85]),
    ("white", [0.8, 0.8, 0.8]),
];
/// One object in this many gets the shiny (half-mirror) finish.
const SHINY_ONE_IN: u64 = 4;

/// Materials `m00_red_matte`, `m01_red_shiny`, ...: the two-digit prefix
/// makes the file's (sorted) order the index order.
fn materials() -> Vec<Material> {
    let mut out = Vec::new();
    for (name, c) in PALETTE {
        let c = DVec3::from_array(c);
        for shiny in [false, true] {
            out.push(Material {
                name: format!(
                    "m{:02}_{name}_{}",
                    out.len(),
                    if shiny { "shiny" } else { "matte" }
                ),
                ambient: c * 0.2,
                diffuse: c,
                specular: DVec3::splat(if shiny { 0.8 } else { 0.2 }),
                shininess: if shiny { 200.0 } else { 20.0 },
                reflection: if shiny { 0.4 } else { 0.0 },
                transmission: 0.0,
                ior: Material::DEFAULT_IOR,
                texture: None,
                physical: crate::scene::Physical::LAMBERTIAN,
                maps: crate::scene::MaterialMaps::NONE,
                alpha: crate::scene::Alpha::OPAQUE,
            });
        }
    }
    out
}

fn pick_material(rng: &mut SplitMix64) -> u32 {
    let colour = rng.below(PALETTE.len() as u64) as u32;
    let shiny = rng.below(SHINY_ONE_IN) == 0;
    colour * 2 + shiny as u32
}

fn random_centre(rng: &mut SplitMix64) -> DVec3 {
    DVec3::new(
        rng.range(-BOX_HALF, BOX_HALF),
        rng.range(-BOX_HALF, BOX_HALF),
        rng.range(-BOX_HALF, BOX_HALF),
    )
}

/// The scene `spec` describes; the same spec always gives the same scene.
pub fn random_scene(spec: &RandomSceneSpec) -> Scene {
    let (n_spheres, n_triangles) = spec.split();
    let cbrt_n = (spec.count.max(1) as f64).cbrt();
    // Separate streams, so the spheres of a mixed scene do not depend on
    // its triangles.
    let mut sphere_rng = SplitMix64::new(spec.seed ^ 0x5350_4845_5245_5300);
    let mut triangle_rng = SplitMix64::new(spec.seed ^ 0x5452_4941_4e47_4c45);

    let sphere_scale = SPHERE_SCALE / cbrt_n;
    let spheres = (0..n_spheres)
        .map(|_| {
            let center = qv(random_centre(&mut sphere_rng));
            // At least 1e-5, so rounding can never make it 0.
            let radius = q(sphere_scale * sphere_rng.range(0.5, 1.5)).max(1e-5);
            let material = pick_material(&mut sphere_rng);
            Sphere {
                center,
                radius,
                material,
            }
        })
        .collect();

    let triangle_scale = TRIANGLE_SCALE / cbrt_n;
    let triangles = if spec.kind == SceneKind::Gears {
        gears(spec.count, spec.seed)
    } else {
        random_triangles(n_triangles, triangle_scale, &mut triangle_rng)
    };

    Scene {
        camera: Camera {
            position: DVec3::new(0.0, 1.5, 8.5),
            look_at: DVec3::ZERO,
            up: DVec3::Y,
            vfov_degrees: 42.0,
        },
        render: RenderSettings {
            width: spec.width,
            height: spec.height,
            min_intensity: 0.05,
            max_depth: 6,
            background: DVec3::new(0.06, 0.08, 0.12),
            shadow_mode: ShadowMode::Ambient,
            samples: 1,
            integrator: Default::default(),
            seed: 0,
            tone_map: Default::default(),
            exposure: 0.0,
            denoise: false,
        },
        environment: None,
        lights: vec![Light {
            position: DVec3::new(5.0, 8.0, 9.0),
            ambient: DVec3::splat(0.25),
            diffuse: DVec3::ONE,
            specular: DVec3::ONE,
            kind: Default::default(),
            reference_distance: None,
        }],
        materials: materials(),
        spheres,
        triangles,
        triangle_normals: Vec::new(),
        triangle_uvs: Vec::new(),
        triangle_second_uvs: Vec::new(),
        triangle_colours: Vec::new(),
        triangle_tangents: Vec::new(),
        textures: Vec::new(),
        animation: None,
        shapes: Vec::new(),
        instances: Vec::new(),
    }
}

/// `n` triangles of random shapes around random centres (see the module comment).
fn random_triangles(n: usize, scale: f64, rng: &mut SplitMix64) -> Vec<Triangle> {
    (0..n)
        .map(|_| {
            let centre = random_centre(rng);
            let size = scale * rng.range(0.5, 1.5);
            let material = pick_material(rng);
            // Three vertices on a sphere of radius `size` around the
            // centre; redraw slivers (area under a tenth of size^2).
            loop {
                let vertices = [0; 3].map(|_| qv(centre + size * rng.unit_vector()));
                let area = 0.5
                    * (vertices[1] - vertices[0])
                        .cross(vertices[2] - vertices[0])
                        .length();
                if area >= 0.1 * size * size {
                    break Triangle::flat(vertices, material);
                }
            }
        })
        .collect()
}

/// Outline vertices of a full-size gear: 36 teeth of 4 vertices each.
pub const GEAR_OUTLINE_VERTICES: usize = 144;
/// Tip radius of the gears is `GEAR_SCALE / cbrt(number of gears)`.
pub const GEAR_SCALE: f64 = 1.6;
/// Triangles of a gear with `v` outline vertices: two faces fanned into
/// `v - 2` triangles each, and a rim of `v` quads.
const fn gear_triangle_count(v: usize) -> usize {
    4 * v - 4
}

/// The gears scene: gear wheels whose flat faces are
/// 144-vertex polygons, fan-triangulated from their first vertex as an OBJ
/// reader does an n-gon (142 triangles per face, most of them long and
/// thin, all sharing one vertex), and whose rims are quads, placed at random
/// centres and orientations; plus a floor, a regular polygon fanned the same
/// way. Exactly `count` triangles: 4,578 gives the gears benchmark scene, 8
/// gears of 572 triangles on a floor quad.
///
/// The outline's teeth make it non-convex, so a fan from one of its
/// vertices also covers part of the gaps between the teeth on the far side
/// (it is a triangulation only of a convex polygon); the OBJ gears this
/// scene stands for were fanned the same way, and the bench needs the triangles' shapes, not
/// a faithful gear.
///
/// Sizes: the floor takes 2 triangles (up to 17, absorbing what the gears
/// cannot); the rest goes to `ceil(rest / 572)` gears, whose outlines have
/// the same multiple of 4 vertices, up to 144, or 4 more for some of them.
/// Below 14 triangles there are no gears, only the floor.
pub fn gears(count: usize, seed: u64) -> Vec<Triangle> {
    let mut rng = SplitMix64::new(seed ^ 0x4745_4152_5300_0000);
    let full = gear_triangle_count(GEAR_OUTLINE_VERTICES);
    let rest = count.saturating_sub(2);
    let (n_gears, base_v, bigger) = if rest < gear_triangle_count(4) {
        (0, 0, 0)
    } else {
        let n = rest.div_ceil(full);
        let v = 4 * ((rest / n + 4) / 16);
        let extra = (rest - n * gear_triangle_count(v)) / 16;
        (n, v, extra)
    };
    let mut triangles = Vec::with_capacity(count);
    let radius = GEAR_SCALE / (n_gears.max(1) as f64).cbrt();
    for g in 0..n_gears {
        let v = if g < bigger { base_v + 4 } else { base_v };
        let centre = random_centre(&mut rng);
        let axis = rng.unit_vector();
        let phase = rng.range(0.0, std::f64::consts::TAU);
        let material = pick_material(&mut rng);
        gear(&mut triangles, v, centre, axis, phase, radius, material);
    }
    let floor = count - triangles.len();
    fan_polygon(&mut triangles, floor + 2);
    triangles
}

/// One gear with `v` outline vertices (a multiple of 4) into `out`.
fn gear(
    out: &mut Vec<Triangle>,
    v: usize,
    centre: DVec3,
    axis: DVec3,
    phase: f64,
    radius: f64,
    material: u32,
) {
    let (u, w) = axis.any_orthonormal_pair();
    let half_width = 0.1 * radius;
    let pitch = std::f64::consts::TAU / (v / 4) as f64;
    // Each tooth: root, tip, tip, root, then the gap to the next tooth.
    let profile = [(0.0, 0.85), (0.2, 1.0), (0.45, 1.0), (0.65, 0.85)];
    let outline: Vec<DVec3> = (0..v)
        .map(|i| {
            let (at, r) = profile[i % 4];
            let angle = phase + pitch * ((i / 4) as f64 + at);
            centre + radius * r * (angle.cos() * u + angle.sin() * w)
        })
        .collect();
    let front: Vec<DVec3> = outline.iter().map(|&p| qv(p + half_width * axis)).collect();
    let back: Vec<DVec3> = outline.iter().map(|&p| qv(p - half_width * axis)).collect();
    for face in [&front, &back] {
        for i in 1..v - 1 {
            out.push(Triangle::flat([face[0], face[i], face[i + 1]], material));
        }
    }
    for i in 0..v {
        let j = (i + 1) % v;
        out.push(Triangle::flat([front[i], front[j], back[j]], material));
        out.push(Triangle::flat([front[i], back[j], back[i]], material));
    }
}

/// The floor under the objects: a regular polygon of `corners` (at least 3)
/// fanned from its first corner, white and matte.
fn fan_polygon(out: &mut Vec<Triangle>, corners: usize) {
    let white_matte = 2 * (PALETTE.len() as u32 - 1);
    let corner = |i: usize| {
        let angle = std::f64::consts::FRAC_PI_4 + std::f64::consts::TAU * i as f64 / corners as f64;
        qv(DVec3::new(
            8.0 * angle.cos(),
            -BOX_HALF - 0.5,
            8.0 * angle.sin(),
        ))
    };
    for i in 1..corners - 1 {
        out.push(Triangle::flat(
            [corner(0), corner(i), corner(i + 1)],
            white_matte,
        ));
    }
}

// ---------------------------------------------------------------- writing

/// Writes `scene` as a scene file that `kdray::scene::load_scene` reads back
/// as an equal `Scene` (given distinct material names whose sorted order is
/// their index order, as the generator's are), through the scene reader's
/// own serde types (`kdray::scene::scene_text`). `header` becomes comment
/// lines in TOML (JSON has no comments; it is left out there).
pub fn scene_file_text(scene: &Scene, format: SceneFormat, header: &str) -> Result<String, String> {
    let text = crate::scene::scene_text(scene, format)?;
    Ok(match format {
        SceneFormat::Toml => {
            let mut out = String::with_capacity(header.len() + text.len() + 16);
            for line in header.lines() {
                let _ = writeln!(out, "# {line}");
            }
            out.push('\n');
            out.push_str(&text);
            out
        }
        SceneFormat::Json => text,
    })
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;

    #[test]
    fn every_scene_kind_is_found_by_its_name() {
        crate::choice::assert_names_round_trip::<SceneKind>();
    }

    #[test]
    fn splitmix64_matches_the_reference_sequence() {
        // First outputs for seed 1234567 of the reference C implementation
        // (Vigna's splitmix64.c).
        let mut rng = SplitMix64::new(1234567);
        let got: Vec<u64> = (0..3).map(|_| rng.next_u64()).collect();
        assert_eq!(
            got,
            [
                6457827717110365317,
                3203168211198807973,
                9817491932198370423
            ]
        );
    }

    #[test]
    fn same_seed_same_scene_other_seed_other_scene() {
        for kind in [SceneKind::Spheres, SceneKind::Triangles, SceneKind::Mixed] {
            let spec = RandomSceneSpec::new(kind, 300);
            let a = random_scene(&spec);
            assert_eq!(a, random_scene(&spec), "{kind:?}");
            assert_eq!(a.object_count(), 300);
            let b = random_scene(&RandomSceneSpec {
                seed: spec.seed + 1,
                ..spec
            });
            assert_ne!(a, b, "{kind:?}");
        }
    }

    #[test]
    fn generator_output_is_pinned() {
        // Guards against accidental changes to the generator: the benchmark
        // figures in docs/benchmarks.md were measured on these scenes.
        let s = random_scene(&RandomSceneSpec::new(SceneKind::Spheres, 1000));
        let first = s.spheres[0];
        let sum: f64 = s.spheres.iter().map(|s| s.center.x + s.radius).sum();
        assert_eq!(
            (first.center, first.radius, first.material, q(sum)),
            PINNED_FIRST_SPHERE
        );
    }

    // The generator's output when the benchmark was first run.
    const PINNED_FIRST_SPHERE: (DVec3, f64, u32, f64) = (
        DVec3::new(-1.544292, 1.994805, -0.820383),
        0.058459,
        6,
        38.992406,
    );

    #[test]
    fn mixed_splits_and_sizes_shrink() {
        let spec = RandomSceneSpec::new(SceneKind::Mixed, 7);
        assert_eq!(spec.split(), (4, 3));
        let s = random_scene(&spec);
        assert_eq!((s.spheres.len(), s.triangles.len()), (4, 3));
        let mean_radius = |n: usize| {
            let s = random_scene(&RandomSceneSpec::new(SceneKind::Spheres, n));
            s.spheres.iter().map(|s| s.radius).sum::<f64>() / n as f64
        };
        let (r1k, r8k) = (mean_radius(1000), mean_radius(8000));
        assert!((r1k / r8k - 2.0).abs() < 0.1, "{r1k} {r8k}");
    }

    #[test]
    fn gears_give_exactly_count_triangles_of_non_zero_area() {
        for count in [1, 2, 3, 13, 14, 26, 100, 573, 1000, 4578, 12_345] {
            let spec = RandomSceneSpec::new(SceneKind::Gears, count);
            let s = random_scene(&spec);
            assert_eq!(s.triangles.len(), count, "count {count}");
            assert!(s.spheres.is_empty());
            assert_eq!(s, random_scene(&spec), "deterministic");
            for t in &s.triangles {
                let n = (t.vertices[1] - t.vertices[0]).cross(t.vertices[2] - t.vertices[0]);
                assert!(n.length() > 1e-9, "count {count}: {t:?}");
                assert!((t.material as usize) < s.materials.len());
            }
        }
    }

    /// 4,578 triangles are the gears benchmark scene: 8 gears of 572 triangles (two
    /// faces fanned from their first vertex into 142 triangles each, and a
    /// rim of 144 quads), then a floor quad. Most face triangles are long and
    /// thin.
    #[test]
    fn gears_scene_of_4578_triangles_is_eight_gears_and_a_floor() {
        let s = random_scene(&RandomSceneSpec::new(SceneKind::Gears, 4578));
        let gear = gear_triangle_count(GEAR_OUTLINE_VERTICES);
        assert_eq!(gear, 572);
        for g in 0..8 {
            let ts = &s.triangles[g * gear..(g + 1) * gear];
            for face in [&ts[..142], &ts[142..284]] {
                let apex = face[0].vertices[0];
                assert!(
                    face.iter().all(|t| t.vertices[0] == apex),
                    "gear {g}: a fan"
                );
                assert!(face.iter().all(|t| t.material == face[0].material));
                // Longest edge over the height on it.
                let thin = face
                    .iter()
                    .filter(|t| {
                        let [a, b, c] = t.vertices;
                        let longest = (b - a).length().max((c - b).length()).max((a - c).length());
                        let area2 = (b - a).cross(c - a).length();
                        longest * longest / area2 > 10.0
                    })
                    .count();
                assert!(thin > 71, "gear {g}: {thin} of 142 face triangles are thin");
            }
        }
        let floor = &s.triangles[8 * gear..];
        assert_eq!(floor.len(), 2);
        assert!(floor
            .iter()
            .all(|t| t.vertices.iter().all(|v| v.y == -BOX_HALF - 0.5)));
    }

    #[test]
    fn objects_are_valid_and_inside_the_box() {
        let s = random_scene(&RandomSceneSpec::new(SceneKind::Mixed, 2000));
        let limit = BOX_HALF + 1.0;
        for sp in &s.spheres {
            assert!(sp.radius > 0.0 && sp.center.abs().max_element() <= limit);
            assert!((sp.material as usize) < s.materials.len());
        }
        for t in &s.triangles {
            let n = (t.vertices[1] - t.vertices[0]).cross(t.vertices[2] - t.vertices[0]);
            assert!(n.length() > 0.0);
            assert!(t.vertices.iter().all(|v| v.abs().max_element() <= limit));
        }
        let mut names: Vec<_> = s.materials.iter().map(|m| m.name.clone()).collect();
        let before = names.clone();
        names.sort();
        assert_eq!(names, before, "material names must sort in index order");
    }

    #[test]
    fn written_files_read_back_equal() {
        for kind in [SceneKind::Spheres, SceneKind::Triangles, SceneKind::Mixed] {
            let scene = random_scene(&RandomSceneSpec::new(kind, 25));
            for (format, ext) in [(SceneFormat::Toml, "toml"), (SceneFormat::Json, "json")] {
                let text = scene_file_text(&scene, format, "a header\nline two").unwrap();
                let parsed = crate::scene::parse_scene(
                    &text,
                    Path::new(&format!("generated.{ext}")),
                    format,
                )
                .unwrap_or_else(|e| panic!("{kind:?} {ext}: {e}\n{text}"));
                assert_eq!(parsed, scene, "{kind:?} {ext}");
            }
        }
    }

    #[test]
    fn odd_material_names_survive() {
        let mut scene = random_scene(&RandomSceneSpec::new(SceneKind::Mixed, 4));
        // Names needing quotes or escapes in TOML and JSON, still in sorted order.
        for (i, m) in scene.materials.iter_mut().enumerate() {
            m.name = format!("{i:02} torus.obj:\"gold\"\\ \u{7f}\n");
        }
        for format in [SceneFormat::Toml, SceneFormat::Json] {
            let text = scene_file_text(&scene, format, "").unwrap();
            let parsed = crate::scene::parse_scene(&text, Path::new("generated"), format)
                .unwrap_or_else(|e| panic!("{format:?}: {e}\n{text}"));
            assert_eq!(parsed, scene, "{format:?}");
        }
        // Two materials of one name cannot be written as a table of names.
        scene.materials[1].name = scene.materials[0].name.clone();
        assert!(scene_file_text(&scene, SceneFormat::Json, "").is_err());
    }
}
