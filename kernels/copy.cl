// The bandwidth reference for benchmarks: copy the active bricks of one field to
// another, one row per work-item like the operations.
kernel void copy_bricks(global const real* from, global real* to, global const uint* bricks, global const uint* slot) {
    const size_t at = (size_t)slot[bricks[get_group_id(0)]] * BRICK_CELLS + BRICK * get_local_id(0);
    vstore8(load_row(from, at), 0, to + at);
}
