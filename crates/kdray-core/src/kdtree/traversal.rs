//! The choice of k-d walk, and the CPU queries for each: every walk visits
//! the same leaves with the same intervals (see each module), so they return
//! the same hits; they differ in how they reach the next leaf.

use crate::geometry::Ray;

use super::traverse::SHORT_STACK_DEPTH;
use super::walk_observer::WalkObserver;
use super::walk_step::{Hit, WalkCost, WalkQuery, WalkScene};
use super::{traverse, traverse_ropes};

/// Which stackless walk the shader (and its CPU mirror) runs.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Default, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "kebab-case")]
pub enum Traversal {
    /// kd-restart with push-down (Foley & Sugerman 2005; Horn et al. 2007):
    /// after each leaf, descend again from the restart node.
    Restart,
    /// Ropes (Popov et al. 2007): after each leaf, descend from the node
    /// beyond the face the ray leaves through.
    Ropes,
    /// kd-restart with a short stack (Horn et al. 2007): after each leaf,
    /// resume at the last far child remembered, restarting when none is left.
    /// The default: fastest on every benchmark scene on lavapipe once each
    /// walk has a pipeline of its own (docs/design.md, "Traversal").
    #[default]
    ShortStack,
}

impl Traversal {
    pub const ALL: [Traversal; 3] = [Traversal::Restart, Traversal::Ropes, Traversal::ShortStack];

    /// The name used on the command line and in `--stats`.
    pub fn name(self) -> &'static str {
        match self {
            Traversal::Restart => "restart",
            Traversal::Ropes => "ropes",
            Traversal::ShortStack => "short-stack",
        }
    }

    /// Nearest hit with 0 < t <= t_limit.
    pub fn closest_hit(self, scene: WalkScene, ray: &Ray, t_limit: f32) -> Option<Hit> {
        let any = false;
        self.walk_counted(scene, WalkQuery { ray, t_limit, any }).0
    }

    /// Whether anything is hit with 0 < t < t_limit (shadow rays).
    pub fn any_hit(self, scene: WalkScene, ray: &Ray, t_limit: f32) -> bool {
        let any = true;
        self.walk_counted(scene, WalkQuery { ray, t_limit, any })
            .0
            .is_some()
    }

    /// The hit `query` asks for, and the work the walk did (as its shader
    /// counts it).
    pub fn walk_counted(self, scene: WalkScene, query: WalkQuery) -> (Option<Hit>, WalkCost) {
        self.walk_observed(scene, query, &mut ())
    }

    /// [`Traversal::walk_counted`], reporting every step to `observer`.
    pub fn walk_observed<O: WalkObserver>(
        self,
        scene: WalkScene,
        query: WalkQuery,
        observer: &mut O,
    ) -> (Option<Hit>, WalkCost) {
        let WalkScene { tree, prims, .. } = scene;
        match self {
            Traversal::Restart => traverse::walk_observed(tree, prims, query, 0, observer),
            Traversal::Ropes => traverse_ropes::walk_observed(scene, query, observer),
            Traversal::ShortStack => {
                traverse::walk_observed(tree, prims, query, SHORT_STACK_DEPTH, observer)
            }
        }
    }

    /// The next walk, for the window's key that cycles them.
    pub fn next(self) -> Traversal {
        let i = Traversal::ALL.iter().position(|&t| t == self).unwrap_or(0);
        Traversal::ALL[(i + 1) % Traversal::ALL.len()]
    }
}

impl std::fmt::Display for Traversal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl crate::choice::Choice for Traversal {
    const ALL: &'static [Self] = &Traversal::ALL;

    fn name(self) -> &'static str {
        Traversal::name(self)
    }

    fn help(self) -> &'static str {
        match self {
            Traversal::Restart => "kd-restart with push-down",
            Traversal::Ropes => "ropes between neighbouring leaves (Popov et al. 2007)",
            Traversal::ShortStack => "kd-restart with a three-entry short stack (Horn et al. 2007)",
        }
    }
}
