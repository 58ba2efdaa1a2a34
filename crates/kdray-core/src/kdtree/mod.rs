//! The k-d tree: built on the CPU ([`build`]: the surface area heuristic
//! with perfect splits, or the seed's median split), stored flat
//! ([`KdNode`]s depth first + a leaf-object list), and walked by CPU
//! mirrors of the shader's stackless walks ([`Traversal`]: [`traverse`], the
//! restart walk, plain or with a short stack; [`traverse_ropes`] over
//! [`Ropes`]), built from the steps they share ([`walk_step`]), that the
//! tests check against brute force. This file is the module's face: the
//! tree and its constructors live in `build`, its shape in `tree_stats`,
//! its node and rope records in `nodes`.

mod binned;
mod build;
mod build_params;
mod clip;
mod events;
mod few;
mod median;
mod nodes;
pub mod ropes;
mod sah;
mod split;
mod strategy;
pub mod traversal;
pub mod traverse;
pub mod traverse_ropes;
mod tree_stats;
pub mod walk_observer;
pub mod walk_step;

pub use build::{build, build_primitives, build_with_threads, KdTree};
pub use build_params::{
    triangle_test_cost, BuildParams, BuildStrategy, BINNED_PAST_OBJECTS, EMPTY_BONUS,
    LARGE_SCENE_OBJECTS, LARGE_SCENE_TRIANGLE_COST, SMALL_SCENE_OBJECTS, SPHERE_TEST_COST,
};
pub use nodes::{KdNode, LeafRopes};
pub use ropes::Ropes;
pub use traversal::Traversal;
pub use tree_stats::TreeStats;
pub use walk_observer::{WalkEvent, WalkObserver};
pub use walk_step::{WalkQuery, WalkScene};
