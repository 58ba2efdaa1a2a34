//! The texture level of detail at a hit, by ray cones (Akenine-Möller et
//! al., "Texture Level of Detail Strategies for Real-Time Ray Tracing", Ray
//! Tracing Gems, chapter 20): the CPU mirror of `pixel_spread_angle` and
//! `texture_lod` in shaders/texture.wgsl, in the same f32 steps.
//!
//! A pixel's cone leaves the eye with width 0 and spread angle
//! `atan(2 tan(vfov / 2) / height)` (height in pixels). Its width at a hit
//! is the spread angle times the path's length from the eye: the sum of the
//! hit distances of the rays before it and this one, through mirror
//! reflections and refractions alike (the flat-mirror rule: a surface's
//! curvature does not widen or narrow the cone, and refraction does not
//! change its angle).

use glam::{Vec2, Vec3};

/// The spread angle of one pixel's cone, in radians.
pub fn pixel_spread_angle(tan_half_vfov: f32, height: u32) -> f32 {
    (2.0 * tan_half_vfov / height as f32).atan()
}

/// lambda = Delta + log2(cone_width) - log2(|n . d|), Delta = 0.5
/// log2(texel area / world area) of the triangle with corners `v` and
/// texture coordinates `uvs` on a `size` texture (the texel area is its
/// area in texture coordinates times width x height), `n` its unit
/// geometric normal and `d` the unit ray direction. 0 (the base level)
/// where a factor is not positive: a degenerate triangle or mapping, a ray
/// in the triangle's plane, a cone of width 0.
pub fn texture_lod(v: &[Vec3; 3], uvs: [Vec2; 3], size: Vec2, dir: Vec3, cone_width: f32) -> f32 {
    let n = (v[1] - v[0]).cross(v[2] - v[0]);
    let world_area = n.length();
    let t1 = uvs[1] - uvs[0];
    let t2 = uvs[2] - uvs[0];
    let texel_area = (t1.x * t2.y - t2.x * t1.y).abs() * size.x * size.y;
    let cosine = n.dot(dir).abs() / world_area;
    if !(world_area > 0.0 && texel_area > 0.0 && cosine > 0.0 && cone_width > 0.0) {
        return 0.0;
    }
    0.5 * (texel_area / world_area).log2() + cone_width.log2() - cosine.log2()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_spread_angle_is_the_angle_one_pixel_subtends_at_the_centre() {
        // vfov 90 degrees, 2 pixels: each pixel spans tan = 1.
        let a = pixel_spread_angle(1.0, 2);
        assert!((a - std::f32::consts::FRAC_PI_4).abs() < 1e-6, "{a}");
        let small = pixel_spread_angle(0.5, 1000);
        assert!((small - 0.001).abs() < 1e-9, "{small}");
    }

    #[test]
    fn lambda_for_a_hand_worked_triangle_and_ray() {
        // A right triangle of legs 2 in the plane z = 0 (world area 2),
        // mapped onto half of a 64 x 16 texture (uv legs 1: uv area 1/2,
        // texel area 512): Delta = 0.5 log2(512 / 2) = 4.
        let v = [
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
        ];
        let uvs = [Vec2::ZERO, Vec2::new(1.0, 0.0), Vec2::new(0.0, 1.0)];
        let size = Vec2::new(64.0, 16.0);
        // Head-on, a cone 1/64 wide: 4 - 6 - 0 = -2 (magnified).
        let head_on = texture_lod(&v, uvs, size, Vec3::new(0.0, 0.0, -1.0), 1.0 / 64.0);
        assert_eq!(head_on, -2.0);
        // At 60 degrees from the normal (|n . d| = 1/2) and a cone 1/4
        // wide: 4 - 2 + 1 = 3.
        let d = Vec3::new(0.75f32.sqrt(), 0.0, -0.5);
        let oblique = texture_lod(&v, uvs, size, d, 0.25);
        assert!((oblique - 3.0).abs() < 1e-5, "{oblique}");
        // The camera of a 90-degree, 2-pixel-high view 4 away: width
        // (pi / 4) x 4 = pi; lambda = 4 + log2(pi) = 5.651.
        let width = pixel_spread_angle(1.0, 2) * 4.0;
        let far = texture_lod(&v, uvs, size, Vec3::new(0.0, 0.0, -1.0), width);
        assert!(
            (far - (4.0 + std::f32::consts::PI.log2())).abs() < 1e-5,
            "{far}"
        );
    }

    #[test]
    fn degenerate_inputs_give_the_base_level() {
        let v = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let uvs = [Vec2::ZERO, Vec2::X, Vec2::Y];
        let size = Vec2::splat(8.0);
        let d = Vec3::NEG_Z;
        assert_eq!(texture_lod(&v, [Vec2::ZERO; 3], size, d, 1.0), 0.0);
        assert_eq!(texture_lod(&[Vec3::ZERO; 3], uvs, size, d, 1.0), 0.0);
        assert_eq!(texture_lod(&v, uvs, size, Vec3::X, 1.0), 0.0);
        assert_eq!(texture_lod(&v, uvs, size, d, 0.0), 0.0);
        assert!(texture_lod(&v, uvs, size, d, 1.0) > 0.0);
    }
}
