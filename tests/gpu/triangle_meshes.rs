//! The meshes the watertightness tests (triangle_edges.rs) aim rays at:
//! fans around a vertex (flat or cone-shaped), strips, subdivided quads and
//! triangulated convex polygons, as proptest strategies, lying in axis
//! planes or turned at random, near the origin or 1e4 away. Each vertex is
//! computed once in f32, so triangles sharing it hold the same bits, as in
//! a real mesh.

use std::collections::HashMap;

use glam::{DQuat, DVec3, Vec3};
use kdray::geometry::{Primitives, TriangleF32};
use proptest::prelude::*;

/// A triangle mesh: f32 vertices, each stored once, and index triples, all
/// wound the same way (counter-clockwise seen from the local +z side).
#[derive(Debug, Clone)]
pub(crate) struct Mesh {
    pub(crate) vertices: Vec<Vec3>,
    pub(crate) triangles: Vec<[usize; 3]>,
}

impl Mesh {
    pub(crate) fn triangle(&self, i: usize) -> TriangleF32 {
        TriangleF32 {
            v: self.triangles[i].map(|k| self.vertices[k]),
        }
    }

    pub(crate) fn primitives(&self) -> Primitives {
        Primitives {
            spheres: Vec::new(),
            triangles: (0..self.triangles.len())
                .map(|i| self.triangle(i))
                .collect(),
            alpha: None,
        }
    }

    /// The largest coordinate magnitude of the vertices.
    pub(crate) fn magnitude(&self) -> f32 {
        self.vertices
            .iter()
            .map(|v| v.abs().max_element())
            .fold(0.0, f32::max)
    }

    /// How many triangles use each undirected edge.
    pub(crate) fn edge_uses(&self) -> HashMap<(usize, usize), usize> {
        let mut uses = HashMap::new();
        for t in &self.triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                *uses.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            }
        }
        uses
    }

    /// Edges of two triangles: the rays' targets (their ends are the shared vertices).
    pub(crate) fn shared_edges(&self) -> Vec<(usize, usize)> {
        let mut edges: Vec<_> = self
            .edge_uses()
            .into_iter()
            .filter(|&(_, n)| n >= 2)
            .map(|(e, _)| e)
            .collect();
        edges.sort();
        edges
    }

    /// Edges of one triangle: the mesh's outer boundary.
    pub(crate) fn boundary_edges(&self) -> Vec<(usize, usize)> {
        self.edge_uses()
            .into_iter()
            .filter(|&(_, n)| n == 1)
            .map(|(e, _)| e)
            .collect()
    }
}

/// Local 2D points with heights, placed in the world: `axis_plane` keeps the
/// local axes (a flat mesh then lies exactly in a z = const plane, the x, y,
/// z roles permuted by `permutation`), otherwise a random turn.
#[derive(Debug, Clone)]
pub(crate) struct Placement {
    scale: f64,
    offset: DVec3,
    turn: Option<DQuat>,
    permutation: usize,
}

impl Placement {
    pub(crate) fn place(&self, local: DVec3) -> Vec3 {
        let p = match self.turn {
            Some(q) => q * local,
            None => local,
        };
        let p = match self.permutation {
            0 => p,
            1 => DVec3::new(p.y, p.z, p.x),
            _ => DVec3::new(p.z, p.x, p.y),
        };
        (p * self.scale + self.offset).as_vec3()
    }
}

pub(crate) fn placement() -> impl Strategy<Value = Placement> {
    let offset = prop_oneof![
        1 => Just(DVec3::ZERO),
        1 => (-10.0f64..10.0, -10.0f64..10.0, -10.0f64..10.0).prop_map(|(x, y, z)| DVec3::new(x, y, z)),
        // Large coordinates: f32 spacing near 1e4 is 1e-3.
        1 => (-1e4f64..1e4, -1e4f64..1e4, -1e4f64..1e4).prop_map(|(x, y, z)| DVec3::new(x, y, z)),
    ];
    let turn = prop_oneof![
        1 => Just(None),
        1 => (-3.2f64..3.2, -3.2f64..3.2, -3.2f64..3.2)
            .prop_map(|(a, b, c)| Some(DQuat::from_euler(glam::EulerRot::XYZ, a, b, c))),
    ];
    (0.05f64..20.0, offset, turn, 0usize..3).prop_map(|(scale, offset, turn, permutation)| {
        Placement {
            scale,
            offset,
            turn,
            permutation,
        }
    })
}

/// Heights: flat (in an axis plane when not turned), or a bumpy surface.
pub(crate) fn heights(n: usize) -> impl Strategy<Value = Vec<f64>> {
    prop_oneof![
        1 => Just(vec![0.0; n]),
        1 => prop::collection::vec(-0.5f64..0.5, n),
    ]
}

/// Orients every triangle counter-clockwise in local (x, y).
pub(crate) fn build(
    local: Vec<DVec3>,
    mut triangles: Vec<[usize; 3]>,
    placement: &Placement,
) -> Mesh {
    for t in &mut triangles {
        let (a, b, c) = (local[t[0]], local[t[1]], local[t[2]]);
        if (b - a).truncate().perp_dot((c - a).truncate()) < 0.0 {
            t.swap(1, 2);
        }
    }
    Mesh {
        vertices: local.iter().map(|&p| placement.place(p)).collect(),
        triangles,
    }
}

/// A closed fan of 3 - 9 triangles around vertex 0 (a cone when the heights
/// differ); no gap between spokes reaches half a turn.
pub(crate) fn fan() -> impl Strategy<Value = Mesh> {
    (3usize..10)
        .prop_flat_map(|n| {
            (
                prop::collection::vec((0.1f64..1.0, 0.3f64..1.0), n),
                heights(n + 1),
                placement(),
            )
        })
        .prop_map(|(spokes, h, placement)| {
            let n = spokes.len();
            // Spoke i at angle (i + jitter) 2 pi / n: gaps stay below pi.
            let mut local = vec![DVec3::new(0.0, 0.0, h[n])];
            for (i, &(jitter, r)) in spokes.iter().enumerate() {
                let angle = (i as f64 + 0.4 * jitter) * std::f64::consts::TAU / n as f64;
                local.push(DVec3::new(r * angle.cos(), r * angle.sin(), h[i]));
            }
            let triangles = (0..n).map(|i| [0, 1 + i, 1 + (i + 1) % n]).collect();
            build(local, triangles, &placement)
        })
}

/// A strip of 2 - 8 triangles, each sharing an edge with the next.
pub(crate) fn strip() -> impl Strategy<Value = Mesh> {
    (2usize..9)
        .prop_flat_map(|n| {
            (
                prop::collection::vec(-0.2f64..0.2, n + 2),
                heights(n + 2),
                placement(),
            )
        })
        .prop_map(|(jitter, h, placement)| {
            let local = (0..jitter.len())
                .map(|i| DVec3::new(0.5 * i as f64 + jitter[i], (i % 2) as f64, h[i]))
                .collect();
            let triangles = (0..jitter.len() - 2).map(|i| [i, i + 1, i + 2]).collect();
            build(local, triangles, &placement)
        })
}

/// A grid of n x m cells, each split along one of its diagonals.
pub(crate) fn subdivided_quad() -> impl Strategy<Value = Mesh> {
    (1usize..5, 1usize..5)
        .prop_flat_map(|(n, m)| {
            (
                Just((n, m)),
                prop::collection::vec(any::<bool>(), n * m),
                heights((n + 1) * (m + 1)),
                placement(),
            )
        })
        .prop_map(|((n, m), diagonals, h, placement)| {
            let id = |i: usize, j: usize| j * (n + 1) + i;
            let mut local = Vec::new();
            for j in 0..=m {
                for i in 0..=n {
                    local.push(DVec3::new(
                        i as f64 / n as f64,
                        j as f64 / m as f64,
                        h[id(i, j)],
                    ));
                }
            }
            let mut triangles = Vec::new();
            for j in 0..m {
                for i in 0..n {
                    let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                    if diagonals[j * n + i] {
                        triangles.extend([[a, b, c], [a, c, d]]);
                    } else {
                        triangles.extend([[a, b, d], [b, c, d]]);
                    }
                }
            }
            build(local, triangles, &placement)
        })
}

/// A convex polygon of 4 - 10 vertices on an ellipse, triangulated from one
/// vertex: its diagonals are the shared edges, long and thin triangles included.
pub(crate) fn triangulated_polygon() -> impl Strategy<Value = Mesh> {
    (4usize..11)
        .prop_flat_map(|n| {
            (
                prop::collection::vec(0.0f64..1.0, n),
                0.05f64..1.0,
                placement(),
            )
        })
        .prop_map(|(mut angles, aspect, placement)| {
            angles.sort_by(f64::total_cmp);
            angles.dedup_by(|a, b| (*a - *b).abs() < 1e-3);
            while angles.len() < 3 {
                let next = angles.last().copied().unwrap_or(0.0) + 0.3;
                angles.push(next);
            }
            let local: Vec<DVec3> = angles
                .iter()
                .map(|&u| {
                    let a = u * std::f64::consts::TAU;
                    DVec3::new(a.cos(), aspect * a.sin(), 0.0)
                })
                .collect();
            let triangles = (1..local.len() - 1).map(|i| [0, i, i + 1]).collect();
            build(local, triangles, &placement)
        })
}

pub(crate) fn mesh() -> impl Strategy<Value = Mesh> {
    prop_oneof![2 => fan(), 1 => strip(), 1 => subdivided_quad(), 1 => triangulated_polygon()]
}
