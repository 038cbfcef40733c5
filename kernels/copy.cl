// The bandwidth reference for benchmarks: copy the active bricks of one field to
// another, a row kernel (common.cl) like the operations.
kernel void copy_bricks(uint rows, global const real* from, global real* to, global const uint* bricks,
                        global const uint* slot) {
    const uint item = (uint)get_global_id(0);
    if (item >= rows) return;
    const size_t at = (size_t)slot[bricks[item / ROWS_PER_BRICK]] * BRICK_CELLS + BRICK * (item % ROWS_PER_BRICK);
    vstore8(load_row(from, at), 0, to + at);
}
