// Partial sums of r^2, one per active brick, in the OpenMP backend's order: each row's
// cells in x order, then the rows (y fastest, then z). One work-item per row, 64 per
// brick; cells outside the grid add exact zeros.
kernel void residual_norm(global const real* phi, global const real* rhs, global const real* g,
                          global const uint* bricks, global const uint* slot, LEVEL_PARAMS,
                          real coef, global acc* partial) {
    local acc rows[ROWS_PER_BRICK];
    const int lid = (int)get_local_id(0);
    const Row w = brick_row(slot, bx, by, bricks[get_group_id(0)], lid);
    acc s = (acc)0;
    if (w.j < ny && w.k < nz) {
        real r[BRICK];
        vstore8(row_residual(phi, rhs, g, slot, LEVEL_ARGS, w, coef), 0, r);
        for (int q = 0; q < BRICK && w.i0 + q < nx; ++q) s += (acc)r[q] * (acc)r[q];
    }
    rows[lid] = s;
    barrier(CLK_LOCAL_MEM_FENCE);
    if (lid == 0) {
        acc total = (acc)0;
        for (int t = 0; t < ROWS_PER_BRICK; ++t) total += rows[t];
        partial[get_group_id(0)] = total;
    }
}
