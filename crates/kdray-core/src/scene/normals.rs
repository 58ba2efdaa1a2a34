//! Vertex normals for smooth shading: computed from a mesh's faces, and
//! carried through a mesh's transform.

use glam::{DMat3, DVec3};

/// Angle-weighted vertex normals (Thürmer and Wüthrich 1998): each triangle
/// adds its unit normal, weighted by its interior angle at the corner, to the
/// vertex of that corner. Unlike area or plain averages this does not depend
/// on how a polygon was split into triangles (a cube's corner gets the
/// diagonal whichever way its faces are cut). `corners` gives each
/// triangle's corners as indices into `vertices` (corners with one index are
/// one vertex); a triangle with an index out of range is left out. The
/// result is per vertex, of unit length, or zero where the faces around a
/// vertex cancel or there are none.
///
/// The weighted normals (three angles, `atan2` each) are computed on all
/// threads, and added to their vertices on one, in the triangles' order: so
/// the sums, and the normals, are the same bits on any number of threads.
/// For the 1.1 M-triangle bunny with `smooth = true` the load went 0.335 ->
/// 0.325 s (medians of eight, two cores); timed by temporary `Instant`s
/// this function still took about 0.10 s of it, and the normals' lookups
/// and writes in the scene's triangles about 0.06 s.
pub fn angle_weighted<T: Sync>(
    vertices: &[DVec3],
    triangles: &[T],
    corners: impl Fn(&T) -> [usize; 3] + Sync,
) -> Vec<DVec3> {
    use rayon::prelude::*;
    let mut weighted = crate::huge_pages::with_capacity(triangles.len());
    weighted.par_extend(
        triangles
            .par_iter()
            .map(|t| corner_weights(vertices, corners(t))),
    );
    let mut sums = vec![DVec3::ZERO; vertices.len()];
    for (t, w) in triangles.iter().zip(&weighted) {
        if let Some(w) = w {
            for (corner, w) in corners(t).into_iter().zip(w) {
                sums[corner] += *w;
            }
        }
    }
    sums.par_iter()
        .map(|&s| unit(s).unwrap_or(DVec3::ZERO))
        .collect()
}

/// What a triangle adds to each of its corners' vertices: its unit normal
/// times its angle there; None where it has no area or an index is out of
/// range.
fn corner_weights(vertices: &[DVec3], corners: [usize; 3]) -> Option<[DVec3; 3]> {
    let [Some(&v0), Some(&v1), Some(&v2)] = corners.map(|i| vertices.get(i)) else {
        return None;
    };
    let v = [v0, v1, v2];
    let normal = unit((v[1] - v[0]).cross(v[2] - v[0]))?; // no area, no direction
    Some([0, 1, 2].map(|k| {
        let (a, b) = (v[(k + 1) % 3] - v[k], v[(k + 2) % 3] - v[k]);
        // atan2 of |a x b| and a.b: accurate for small and large angles.
        let angle = a.cross(b).length().atan2(a.dot(b));
        angle * normal
    }))
}

/// The matrix that carries normals through the linear map `m`: the inverse
/// transpose (normals stay perpendicular to the transformed surface under a
/// non-uniform scale). `m` must be invertible.
pub fn normal_matrix(m: DMat3) -> DMat3 {
    m.inverse().transpose()
}

/// `v` scaled to length 1, or None for the zero vector (or a non-finite
/// one). Safe for finite vectors of any size.
pub fn unit(v: DVec3) -> Option<DVec3> {
    let largest = v.abs().max_element();
    if !(largest > 0.0 && largest.is_finite()) {
        return None;
    }
    let u = (v / largest).normalize();
    u.is_finite().then_some(u)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: DVec3, b: DVec3) -> bool {
        (a - b).abs().max_element() < 1e-12
    }

    /// The unit cube [0, 1]^3, each face cut into two triangles along a
    /// diagonal chosen per face, wound outwards.
    fn cube() -> (Vec<DVec3>, Vec<[usize; 3]>) {
        let vertices: Vec<DVec3> = (0..8)
            .map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64))
            .collect();
        // Quads as corner lists, counter-clockwise seen from outside.
        let quads = [
            [0, 2, 3, 1], // z = 0
            [4, 5, 7, 6], // z = 1
            [0, 1, 5, 4], // y = 0
            [2, 6, 7, 3], // y = 1
            [0, 4, 6, 2], // x = 0
            [1, 3, 7, 5], // x = 1
        ];
        let mut triangles = Vec::new();
        for (i, q) in quads.iter().enumerate() {
            // Alternate the diagonal, so that corners see one or two triangles per face.
            if i % 2 == 0 {
                triangles.push([q[0], q[1], q[2]]);
                triangles.push([q[0], q[2], q[3]]);
            } else {
                triangles.push([q[1], q[2], q[3]]);
                triangles.push([q[1], q[3], q[0]]);
            }
        }
        (vertices, triangles)
    }

    fn normals_of(vertices: &[DVec3], triangles: &[[usize; 3]]) -> Vec<DVec3> {
        angle_weighted(vertices, triangles, |&t| t)
    }

    #[test]
    fn a_cube_corner_gets_the_diagonal_however_its_faces_are_cut() {
        let (vertices, triangles) = cube();
        let normals = normals_of(&vertices, &triangles);
        let centre = DVec3::splat(0.5);
        for (v, n) in vertices.iter().zip(&normals) {
            // Each face adds a right angle at each of its corners, in one
            // triangle or in two halves: the sum points away from the centre.
            let want = (*v - centre).normalize();
            assert!(close(*n, want), "vertex {v}: got {n}, want {want}");
        }
    }

    #[test]
    fn an_octahedron_vertex_gets_its_axis() {
        // +x, -x, +y, -y, +z, -z.
        let vertices: Vec<DVec3> = DVec3::AXES.iter().flat_map(|&a| [a, -a]).collect();
        // The eight faces, one per octant, wound outwards.
        let mut triangles = Vec::new();
        for sx in [0, 1] {
            for sy in [2, 3] {
                for sz in [4, 5] {
                    let t = [sx, sy, sz];
                    let [a, b, c] = t.map(|i| vertices[i]);
                    let outward = (b - a).cross(c - a).dot(a + b + c) > 0.0;
                    triangles.push(if outward { t } else { [sx, sz, sy] });
                }
            }
        }
        let normals = normals_of(&vertices, &triangles);
        for (v, n) in vertices.iter().zip(&normals) {
            assert!(close(*n, *v), "vertex {v}: got {n}");
        }
    }

    #[test]
    fn angle_weights_differ_from_a_plain_average() {
        // At the origin a right-angled face in z = 0 (normal +z) meets a
        // right-angled face in x = 0 (normal +x) cut into two 45 degree
        // triangles: the weighted normal halves the two planes, where the
        // average of the three unit normals would lean 2:1 towards +x.
        let o = DVec3::ZERO;
        let vertices = [o, DVec3::X, DVec3::Y, DVec3::Z, DVec3::new(0.0, 1.0, 1.0)];
        let triangles = [[0, 1, 2], [0, 2, 4], [0, 4, 3]];
        let normals = normals_of(&vertices, &triangles);
        let want = (DVec3::Z + DVec3::X).normalize();
        assert!(close(normals[0], want), "got {}", normals[0]);
    }

    #[test]
    fn unused_vertices_and_zero_area_triangles_give_zero() {
        // Vertex 3 is used by no triangle; [0, 1, 2] is collinear.
        let v = [DVec3::ZERO, DVec3::X, DVec3::X * 2.0, DVec3::Y];
        let normals = angle_weighted(&v, &[[0, 1, 2]], |&t| t);
        assert_eq!(normals, vec![DVec3::ZERO; 4]);
        // A triangle with an index out of range is left out.
        let normals = angle_weighted(&v, &[[0, 1, 3], [0, 3, 4]], |&t| t);
        assert_eq!(normals[3], DVec3::Z);
    }

    /// The normals as one thread adds them, triangle by triangle (the
    /// function before its weights were computed on all threads).
    fn one_thread(vertices: &[DVec3], triangles: &[[usize; 3]]) -> Vec<DVec3> {
        let mut sums = vec![DVec3::ZERO; vertices.len()];
        for &corners in triangles {
            let [Some(&v0), Some(&v1), Some(&v2)] = corners.map(|i| vertices.get(i)) else {
                continue;
            };
            let v = [v0, v1, v2];
            let Some(normal) = unit((v[1] - v[0]).cross(v[2] - v[0])) else {
                continue;
            };
            for k in 0..3 {
                let (a, b) = (v[(k + 1) % 3] - v[k], v[(k + 2) % 3] - v[k]);
                let angle = a.cross(b).length().atan2(a.dot(b));
                sums[corners[k]] += angle * normal;
            }
        }
        sums.into_iter()
            .map(|s| unit(s).unwrap_or(DVec3::ZERO))
            .collect()
    }

    proptest::proptest! {
        /// On random meshes with shared vertices (so that sums have many
        /// terms, whose order changes their bits), degenerate triangles and
        /// indices out of range: the same bits as one thread's sums.
        #[test]
        fn normals_on_threads_are_one_threads_bit_for_bit(
            raw in proptest::collection::vec(-10.0f64..10.0, 3..90),
            picks in proptest::collection::vec(0usize..40, 0..300),
        ) {
            let vertices: Vec<DVec3> = raw.chunks_exact(3).map(DVec3::from_slice).collect();
            let triangles: Vec<[usize; 3]> =
                picks.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
            let got = normals_of(&vertices, &triangles);
            let want = one_thread(&vertices, &triangles);
            let bits = |n: &[DVec3]| n.iter().map(|v| v.to_array().map(f64::to_bits)).collect::<Vec<_>>();
            proptest::prop_assert_eq!(bits(&got), bits(&want));
        }
    }

    #[test]
    fn normals_follow_the_inverse_transpose() {
        // A plane x = z stretched by 2 along x becomes x = 2z, whose normal
        // is (1, 0, -2) / sqrt(5); the plane's own normal is (1, 0, -1).
        let m = DMat3::from_diagonal(DVec3::new(2.0, 1.0, 1.0));
        let n = unit(normal_matrix(m) * DVec3::new(1.0, 0.0, -1.0)).unwrap();
        assert!(close(n, DVec3::new(1.0, 0.0, -2.0) / 5f64.sqrt()), "{n}");
        // A point on the transformed plane stays perpendicular to it.
        let p = m * DVec3::new(1.0, 3.0, 1.0);
        assert!(p.dot(n).abs() < 1e-12);
        // A rotation turns normals as it turns points.
        let r = DMat3::from_rotation_z(0.7);
        assert!(close(normal_matrix(r) * DVec3::X, r * DVec3::X));
    }

    #[test]
    fn unit_of_extreme_vectors() {
        assert_eq!(unit(DVec3::ZERO), None);
        assert_eq!(unit(DVec3::new(f64::NAN, 0.0, 0.0)), None);
        assert_eq!(unit(DVec3::new(1e-300, 0.0, 0.0)), Some(DVec3::X));
        assert_eq!(unit(DVec3::new(0.0, 1e300, 0.0)), Some(DVec3::Y));
    }
}
