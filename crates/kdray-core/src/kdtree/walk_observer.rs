//! What a CPU walk can report step by step (`kdray inspect` shows it): the
//! walks take an observer as a generic parameter, and the un-observed
//! queries pass `()`, whose empty methods compile away, so they run as
//! before. Every event is made where the walk makes the decision it names,
//! from the values the walk itself uses (the shader's, step for step).
//!
//! Node and leaf numbers are indices into `KdTree::nodes`; `t` values are
//! ray parameters (distances along the unit direction, scene units).

/// One step of a walk.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum WalkEvent {
    /// The ray clipped to the scene's box and to `(0, t_limit]`: the
    /// segment the walk searches. None is reported when nothing is left.
    Segment { t_min: f32, t_far: f32 },
    /// An inner node read with the segment `[t_min, t_max]` still to
    /// search in it; the walk goes on in `near`. `crosses`: the segment
    /// reaches `far` past `t_split` too (the restart walks then stop the
    /// near part at `t_split`).
    Node {
        node: usize,
        t_min: f32,
        t_max: f32,
        near: usize,
        far: usize,
        t_split: f32,
        crosses: bool,
    },
    /// A leaf reached, the ray inside it over `[t_min, t_max]` (the rope
    /// walk's `t_max` is the face the ray leaves through).
    Leaf { node: usize, t_min: f32, t_max: f32 },
    /// A leaf the rope walk reached but skips: the ray spends no time in
    /// it (an edge or a corner); the walk descends again from the root.
    SkippedLeaf { node: usize },
    /// One object of the current leaf tested: where the ray meets it (any
    /// `t > 0`, before the query's limit or not), or `None`.
    Tested { object: u32, t: Option<f32> },
    /// The short stack remembered a far child and the segment's end there.
    Push { node: usize, t_max: f32 },
    /// The short stack's top taken: the walk resumes in `node` up to `t_max`.
    Pop { node: usize, t_max: f32 },
    /// A descent starts again from `node` (the restart node; the rope
    /// walk's root after a skipped leaf) at `t_min`.
    Restart { node: usize, t_min: f32 },
    /// The rope walk leaves its leaf through `face` (`2 * axis + 1` for the
    /// upper face) at `t_min` and descends from the rope's `node`.
    Rope {
        face: usize,
        node: usize,
        t_min: f32,
    },
}

/// Receives a walk's events in order. The default ignores them.
pub trait WalkObserver {
    #[inline(always)]
    fn event(&mut self, _event: WalkEvent) {}
}

/// No observer: the plain queries.
impl WalkObserver for () {}

/// Keeps every event, in order.
impl WalkObserver for Vec<WalkEvent> {
    fn event(&mut self, event: WalkEvent) {
        self.push(event);
    }
}
