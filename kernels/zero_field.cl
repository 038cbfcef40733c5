// Sets every cell of a new field (its constant bricks too) to 0, a row kernel
// (common.cl): the device's own threads write it, and on a CPU touch its pages first,
// where PoCL's clEnqueueFillBuffer takes one thread (2.3 s of the bunny at 1024 cells).
kernel void zero_field(uint rows, global real* field) {
    const uint item = (uint)get_global_id(0);
    if (item >= rows) return;
    vstore8((row_t)(0), 0, field + (size_t)BRICK * item);
}
