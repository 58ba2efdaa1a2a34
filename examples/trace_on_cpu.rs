//! Builds a k-d tree over a few spheres and triangles and traces rays
//! through it on the CPU: a nearest-hit query per camera ray, then a shadow
//! query from each hit towards a light. The CPU walk runs the same f32
//! arithmetic as the GPU kernel, so this is also how to inspect one ray.
//!
//! ```sh
//! cargo run --release --example trace_on_cpu
//! ```
//!
//! Prints the scene as characters (`#` lit floor, `.` floor in shadow, `O`
//! lit sphere, `o` sphere in shadow, blank for no hit) and the first hits.
//! tests/gpu/examples.rs checks [`trace`] against brute force and exact values.

use glam::Vec3;
use kdray::geometry::{spawn_offset, Primitives, Ray, SphereF32, TriangleF32, T_INFINITY};
use kdray::kdtree::traverse::{any_hit, any_hit_brute, closest_hit, closest_hit_brute, Hit};
use kdray::kdtree::KdTree;

/// Where the light is: straight above the big sphere.
pub const LIGHT: Vec3 = Vec3::new(0.0, 5.0, -4.0);

/// The floor y = -1 as two triangles, a unit sphere at (0, 0, -4) (object
/// 0) and a row of small spheres on the floor behind it.
pub fn example_primitives() -> Primitives {
    let mut spheres = vec![SphereF32 {
        center: Vec3::new(0.0, 0.0, -4.0),
        radius: 1.0,
    }];
    for i in 0..12 {
        spheres.push(SphereF32 {
            center: Vec3::new(-3.3 + 0.6 * i as f32, -0.75, -7.0),
            radius: 0.25,
        });
    }
    let corner = |x: f32, z: f32| Vec3::new(x, -1.0, z);
    let triangles = vec![
        TriangleF32 {
            v: [corner(-10.0, 2.0), corner(10.0, 2.0), corner(10.0, -20.0)],
        },
        TriangleF32 {
            v: [
                corner(-10.0, 2.0),
                corner(10.0, -20.0),
                corner(-10.0, -20.0),
            ],
        },
    ];
    Primitives {
        spheres,
        triangles,
        alpha: None,
    }
}

/// Rays from the origin through a `columns` x `rows` grid on the plane
/// z = -1 spanning x and y in [-1, 1] (top row first), unit length.
pub fn camera_rays(columns: u32, rows: u32) -> Vec<Ray> {
    let mut rays = Vec::new();
    for row in 0..rows {
        for column in 0..columns {
            let x = -1.0 + 2.0 * (column as f32 + 0.5) / columns as f32;
            let y = 1.0 - 2.0 * (row as f32 + 0.5) / rows as f32;
            rays.push(Ray {
                origin: Vec3::ZERO,
                dir: Vec3::new(x, y, -1.0).normalize(),
            });
        }
    }
    rays
}

/// What one camera ray found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Probe {
    pub hit: Option<Hit>,
    /// Whether something lies between the hit and [`LIGHT`].
    pub in_shadow: bool,
}

/// The unit normal of object `id` at `point`, facing against `dir`.
fn facing_normal(prims: &Primitives, id: u32, point: Vec3, dir: Vec3) -> Vec3 {
    let n = match prims.spheres.get(id as usize) {
        Some(s) => (point - s.center) / s.radius,
        None => prims.triangles[id as usize - prims.spheres.len()].normal(),
    };
    if n.dot(dir) > 0.0 {
        -n
    } else {
        n
    }
}

/// Traces each ray: its nearest hit, then whether the light is blocked from
/// there. With `tree` the queries walk it; without, they test every object
/// (brute force, which the walk must agree with).
pub fn trace(prims: &Primitives, tree: Option<&KdTree>, rays: &[Ray]) -> Vec<Probe> {
    let nearest = |ray: &Ray| match tree {
        Some(tree) => closest_hit(tree, prims, ray, T_INFINITY),
        None => closest_hit_brute(prims, ray, T_INFINITY),
    };
    let blocked = |ray: &Ray, t_limit: f32| match tree {
        Some(tree) => any_hit(tree, prims, ray, t_limit),
        None => any_hit_brute(prims, ray, t_limit),
    };
    rays.iter()
        .map(|ray| {
            let Some(hit) = nearest(ray) else {
                return Probe {
                    hit: None,
                    in_shadow: false,
                };
            };
            // Start the shadow ray just off the surface, so that it does
            // not hit the surface it leaves.
            let point = ray.origin + hit.t * ray.dir;
            let normal = facing_normal(prims, hit.object, point, ray.dir);
            let origin = point + normal * spawn_offset(point, prims.magnitude(hit.object));
            let to_light = LIGHT - origin;
            let shadow_ray = Ray {
                origin,
                dir: to_light.normalize(),
            };
            Probe {
                hit: Some(hit),
                in_shadow: blocked(&shadow_ray, to_light.length()),
            }
        })
        .collect()
}

fn main() {
    let prims = example_primitives();
    let tree = KdTree::for_primitives(&prims);
    let stats = tree.stats();
    println!(
        "{} objects, k-d tree of {} nodes ({} leaves, depth {})",
        prims.len(),
        stats.nodes,
        stats.leaves,
        stats.max_depth
    );

    let (columns, rows) = (64, 24);
    let probes = trace(&prims, Some(&tree), &camera_rays(columns, rows));
    for line in probes.chunks(columns as usize) {
        let text: String = line
            .iter()
            .map(|probe| match (probe.hit, probe.in_shadow) {
                (None, _) => ' ',
                (Some(hit), shadow) if (hit.object as usize) < prims.spheres.len() => {
                    if shadow {
                        'o'
                    } else {
                        'O'
                    }
                }
                (Some(_), true) => '.',
                (Some(_), false) => '#',
            })
            .collect();
        println!("|{text}|");
    }
    for (i, probe) in probes
        .iter()
        .enumerate()
        .filter(|(_, p)| p.hit.is_some())
        .take(5)
    {
        let hit = probe.hit.unwrap();
        println!(
            "ray {i}: object {} at t = {:.4}{}",
            hit.object,
            hit.t,
            if probe.in_shadow { ", in shadow" } else { "" }
        );
    }
}
