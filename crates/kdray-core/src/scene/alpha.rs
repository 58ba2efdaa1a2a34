//! Where a material's surface is there at all: glTF's `alphaMode`,
//! `alphaCutoff` and the base colour's alpha (docs/scene-format.md, "glTF
//! materials"). A point whose alpha fails the test is a hole: every ray
//! passes through it, so the walks' object test finds no hit there
//! (crate::geometry::alpha_test, shaders/alpha.wgsl).

/// How the base colour's alpha is read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum AlphaMode {
    /// Alpha is ignored: the surface is everywhere (glTF's default).
    #[default]
    Opaque,
    /// A point whose alpha is below the cutoff is a hole.
    Mask,
    /// Alpha is the surface's coverage: the path tracer lets a ray through
    /// with probability 1 - alpha (stochastic transparency); the Whitted
    /// integrator reads it as [`AlphaMode::Mask`] with cutoff
    /// [`Alpha::BLEND_WHITTED_CUTOFF`].
    Blend,
}

/// A material's alpha: its mode, its cutoff (MASK) and its constant factor
/// (glTF's baseColorFactor alpha), which multiplies the base-colour
/// texture's alpha where the triangle is textured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Alpha {
    pub mode: AlphaMode,
    /// >= 0; read by [`AlphaMode::Mask`] only.
    pub cutoff: f64,
    /// In [0, 1].
    pub factor: f64,
}

impl Alpha {
    /// glTF's alphaCutoff where a file gives none.
    pub const DEFAULT_CUTOFF: f64 = 0.5;
    /// The cutoff the Whitted integrator reads a BLEND material with: it
    /// traces one ray per sample and has no random numbers to pass a share.
    pub const BLEND_WHITTED_CUTOFF: f64 = 0.5;

    /// A surface that is everywhere, whatever its alpha.
    pub const OPAQUE: Alpha = Alpha {
        mode: AlphaMode::Opaque,
        cutoff: Alpha::DEFAULT_CUTOFF,
        factor: 1.0,
    };

    /// Whether some of the surface may be a hole (the walks test it).
    pub fn is_tested(&self) -> bool {
        self.mode != AlphaMode::Opaque
    }

    /// The cutoff a deterministic test compares alpha with: MASK's own,
    /// BLEND's in the Whitted integrator.
    pub fn fixed_cutoff(&self) -> f64 {
        match self.mode {
            AlphaMode::Blend => Alpha::BLEND_WHITTED_CUTOFF,
            _ => self.cutoff,
        }
    }
}

impl Default for Alpha {
    fn default() -> Self {
        Alpha::OPAQUE
    }
}
