// The frame's parameters, copied from the uniform binding `frame_params` by
// every entry point before its first branch (`read_params`). llvmpipe (Mesa
// 22.3) reads a uniform with one scalar load only where every lane of the
// SIMD group is sure to be active; anywhere else, inside a loop or a branch,
// it loads the word once per lane with a bounds check. The walks and the
// shading read `params` inside their loops: `params.node_count` alone, in the
// short stack's descent loop, was 3.1% of the instructions of the bunny's
// frame. The copy is a private value, which those loops read from a register
// or the stack.
var<private> params: FrameParams;

fn read_params() {
    params = frame_params;
}
