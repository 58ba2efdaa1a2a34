//! The name a `[[lights]]` entry's `kind` gives, before the keys of that
//! kind are read: `point`, `spot` or `directional`.

/// What `kind` names, before its keys are read.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LightShape {
    #[default]
    Point,
    Spot,
    Directional,
}

impl crate::choice::Choice for LightShape {
    const ALL: &'static [Self] = &[Self::Point, Self::Spot, Self::Directional];

    fn name(self) -> &'static str {
        match self {
            Self::Point => "point",
            Self::Spot => "spot",
            Self::Directional => "directional",
        }
    }

    fn help(self) -> &'static str {
        match self {
            Self::Point => "a point light shining every way",
            Self::Spot => "a point light shining into a cone about `direction`",
            Self::Directional => "parallel light travelling along `direction`, from infinitely far",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn light_shapes_round_trip_by_name() {
        crate::choice::assert_names_round_trip::<LightShape>();
    }
}
