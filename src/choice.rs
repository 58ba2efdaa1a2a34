//! Named choices: the enums that the command line, `--stats`, the bench's
//! JSON and its reports spell by name (`kdtree`, `brute`, `spheres`, ...).
//! The library lists each choice's names and help here; the command line
//! (src/bin/kdray) turns them into its flags without the library knowing
//! about the command line.

/// An enum whose values are chosen by name.
pub trait Choice: Copy + PartialEq + Send + Sync + 'static {
    /// Every value, in the order help texts list them.
    const ALL: &'static [Self];

    /// The value's name: lowercase, as flags and reports write it.
    fn name(self) -> &'static str;

    /// One line for `--help`.
    fn help(self) -> &'static str;

    fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|c| c.name() == name)
    }
}

impl Choice for crate::gpu::Accel {
    const ALL: &'static [Self] = &[Self::Kdtree, Self::Brute];

    fn name(self) -> &'static str {
        match self {
            Self::Kdtree => "kdtree",
            Self::Brute => "brute",
        }
    }

    fn help(self) -> &'static str {
        match self {
            Self::Kdtree => "the stackless k-d tree walk",
            Self::Brute => "the seed's loop over every object",
        }
    }
}

impl Choice for crate::bench::SceneKind {
    const ALL: &'static [Self] = &[Self::Spheres, Self::Triangles, Self::Mixed, Self::Gears];

    fn name(self) -> &'static str {
        self.name()
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

#[cfg(test)]
mod tests {
    use super::*;

    fn names_round_trip<T: Choice + std::fmt::Debug>() {
        for &c in T::ALL {
            assert_eq!(T::from_name(c.name()), Some(c));
            assert!(!c.help().is_empty());
        }
        assert_eq!(T::from_name("no-such-choice"), None);
    }

    #[test]
    fn every_choice_is_found_by_its_name() {
        names_round_trip::<crate::gpu::Accel>();
        names_round_trip::<crate::bench::SceneKind>();
    }
}
