//! Named choices: the enums that the command line, `--stats`, the bench's
//! JSON and its reports spell by name (`kdtree`, `brute`, `spheres`, ...).
//! Each choice lists its names and help beside its own type (`Accel` in
//! prepare.rs, `BuildStrategy` in kdtree/build_params.rs, `Traversal` in
//! kdtree/traversal.rs, `SceneKind` in random_scene.rs); the command
//! line (src/bin/kdray) turns them into its flags without the library
//! knowing about the command line.

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

/// Asserts that every value of `T` is found by its name and has help, and
/// that an unknown name finds none: each implementation's own tests call it.
#[cfg(any(test, feature = "test-support"))]
#[doc(hidden)]
pub fn assert_names_round_trip<T: Choice + std::fmt::Debug>() {
    for &c in T::ALL {
        assert_eq!(T::from_name(c.name()), Some(c));
        assert!(!c.help().is_empty());
    }
    assert_eq!(T::from_name("no-such-choice"), None);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, Clone, Copy, PartialEq)]
    enum Shape {
        Round,
        Flat,
    }

    impl Choice for Shape {
        const ALL: &'static [Self] = &[Self::Round, Self::Flat];

        fn name(self) -> &'static str {
            match self {
                Self::Round => "round",
                Self::Flat => "flat",
            }
        }

        fn help(self) -> &'static str {
            "a test shape"
        }
    }

    #[test]
    fn every_choice_is_found_by_its_name() {
        assert_names_round_trip::<Shape>();
        assert_eq!(Shape::from_name("flat"), Some(Shape::Flat));
        assert_eq!(Shape::from_name("Flat"), None, "names are matched exactly");
    }
}
