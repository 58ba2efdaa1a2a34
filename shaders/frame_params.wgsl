// The frame's parameters, copied from the uniform binding `frame_params` by
// every entry point before its first branch (`read_params`). In the kernel
// llvmpipe (Mesa 22.3) compiled for valgrind (AVX2), dumped and read, a
// uniform read inside the walks' loops was a load per lane with a bounds
// check in every iteration: `params.node_count` in the short stack's descent
// loop alone was 3.1% of the instructions counted on the bunny's frame. The
// copy is a private value, which those loops read from a register or the
// stack; natively the frames were 5 - 8% shorter (docs/design.md, "Uniforms
// read once").
var<private> params: FrameParams;

fn read_params() {
    params = frame_params;
}
