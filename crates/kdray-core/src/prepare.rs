//! A scene prepared on the CPU for a kernel ([`PreparedScene`]): the search
//! it runs ([`Accel`]), the f32 primitives, the k-d tree and the arrays in
//! the GPU layout, in one value that can be made on any thread (the
//! window's hot reload makes it on a worker). The `kdray` crate uploads it.

use std::time::Instant;

use crate::geometry::Primitives;
use crate::kdtree::{BuildParams, BuildStrategy, KdTree};
use crate::layout::SceneArrays;
use crate::scene::Scene;

/// Which nearest-hit search the kernel runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Accel {
    /// The stackless k-d tree walk.
    Kdtree,
    /// The seed's loop over every object.
    Brute,
}

impl crate::choice::Choice for Accel {
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

/// A scene with its tree and arrays in the GPU layout, ready to upload.
pub struct PreparedScene {
    pub scene: Scene,
    /// The search it was prepared for, which its frames run unless told
    /// otherwise.
    pub accel: Accel,
    /// The tree the kernel is given. For [`Accel::Brute`] a single leaf of
    /// every object: the kernel's brute-force loop ignores it, and any walk
    /// of it would search like brute force.
    pub tree: KdTree,
    pub arrays: SceneArrays,
    /// How the tree was built (the default for a single leaf).
    pub strategy: BuildStrategy,
    /// Wall time of the tree build, in milliseconds (0 for a single leaf).
    pub build_ms: f64,
    /// Wall time of flattening into the GPU arrays, in milliseconds.
    pub flatten_ms: f64,
}

impl PreparedScene {
    /// Builds what `accel` needs: the k-d tree for [`Accel::Kdtree`], a single
    /// leaf for [`Accel::Brute`].
    pub fn new(scene: Scene, accel: Accel) -> PreparedScene {
        Self::built_by(scene, accel, BuildStrategy::default())
    }

    /// [`PreparedScene::new`] with the k-d tree built by `strategy`.
    /// Instances are flattened first ([`Scene::flatten_instances`]): the
    /// kernels walk one tree over world-space triangles.
    pub fn built_by(scene: Scene, accel: Accel, strategy: BuildStrategy) -> PreparedScene {
        let scene = scene.flattened();
        let prims = Primitives::from_scene(&scene);
        let started = Instant::now();
        let tree = match accel {
            Accel::Kdtree => KdTree::build_for(
                &prims,
                BuildParams {
                    strategy,
                    ..BuildParams::for_primitives(&prims)
                },
            ),
            Accel::Brute => KdTree::single_leaf(prims.len() as u32, prims.scene_bounds()),
        };
        let build_ms = match accel {
            Accel::Kdtree => started.elapsed().as_secs_f64() * 1e3,
            Accel::Brute => 0.0,
        };
        Self::assemble(scene, accel, &prims, tree, strategy, build_ms)
    }

    /// `scene` with a tree built elsewhere over its objects (property
    /// tests choose the build's parameters), for [`Accel::Kdtree`].
    /// `scene`'s instances are flattened first, as the tree's objects must
    /// be.
    pub fn with_tree(scene: Scene, tree: KdTree) -> PreparedScene {
        let scene = scene.flattened();
        let prims = Primitives::from_scene(&scene);
        Self::assemble(
            scene,
            Accel::Kdtree,
            &prims,
            tree,
            BuildStrategy::default(),
            0.0,
        )
    }

    fn assemble(
        scene: Scene,
        accel: Accel,
        prims: &Primitives,
        tree: KdTree,
        strategy: BuildStrategy,
        build_ms: f64,
    ) -> PreparedScene {
        // The root cell is the build's: the objects' box widened by its
        // tolerance ε (kdtree::clip), which the CPU mirrors walk too. An
        // empty scene's is the empty box.
        let tree = if prims.is_empty() {
            KdTree {
                bounds: prims.scene_bounds(),
                ..tree
            }
        } else {
            tree
        };
        let started = Instant::now();
        let arrays = SceneArrays::new(&scene, prims, &tree);
        PreparedScene {
            scene,
            accel,
            tree,
            arrays,
            strategy,
            build_ms,
            flatten_ms: started.elapsed().as_secs_f64() * 1e3,
        }
    }

    /// The scene back, without its tree and arrays.
    pub fn into_scene(self) -> Scene {
        self.scene
    }
}
