// Partial sums of r^2, one per active brick, in the OpenMP backend's order: each row's
// cells in x order, then the rows (y fastest, then z); rows and cells outside the grid
// add exact zeros. Each work-item leaves its rows' sums in local memory, and the
// brick's first adds them up.

// The sum of r^2 over the walk's row, in x order.
ALWAYS_INLINE acc row_sum_squares(global const real* phi, global const real* rhs, global const real* g, LEVEL_PARAMS,
                                  BrickSite s, PlaneWalk w, real coef) {
    real r[BRICK];
    vstore8(plane_residual(phi, rhs, g, LEVEL_ARGS, s, w, coef), 0, r);
    acc sum = (acc)0;
    for (int q = 0; q < BRICK && s.i0 + q < nx; ++q) sum += (acc)r[q] * (acc)r[q];
    return sum;
}

// A brick's 64 row sums in order.
ALWAYS_INLINE acc brick_sum(local const acc* rows) {
    acc total = (acc)0;
    for (int t = 0; t < ROWS_PER_BRICK; ++t) total += rows[t];
    return total;
}

#ifndef SNVR_ROW_KERNELS
// CPUs: a plane kernel (common.cl).
kernel void residual_norm(uint planes, global const real* phi, global const real* rhs, global const real* g,
                          global const uint* bricks, global const uint* slot, LEVEL_PARAMS, real coef,
                          global acc* partial) {
    local acc rows[PLANES_PER_GROUP * BRICK];
    const uint item = (uint)get_global_id(0);
    const int lid = (int)get_local_id(0), lk = lid % BRICK;
    local acc* mine = rows + BRICK * lid;  // row lj of this plane at mine[lj]
    for (int lj = 0; lj < BRICK; ++lj) mine[lj] = (acc)0;
    if (item < planes) {
        const BrickSite s = brick_site(slot, LEVEL_ARGS, bricks[item / BRICK]);
        if (lk < s.nk)
            for (PlaneWalk w = plane_walk(phi, s, lk, -1); w.lj < s.nj; w = plane_step(phi, s, w))
                mine[w.lj] = row_sum_squares(phi, rhs, g, LEVEL_ARGS, s, w, coef);
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    if (item < planes && lk == 0) partial[item / BRICK] = brick_sum(mine);
}

#else
// GPUs: a work-item per row.
kernel void residual_norm(uint rows, global const real* phi, global const real* rhs, global const real* g,
                          global const uint* bricks, global const uint* slot, LEVEL_PARAMS, real coef,
                          global acc* partial) {
    local acc sums[ROWS_PER_GROUP];
    const uint item = (uint)get_global_id(0);
    const int lid = (int)get_local_id(0), r = lid % ROWS_PER_BRICK;
    acc sum = (acc)0;
    if (item < rows) {
        const BrickSite s = brick_site(slot, LEVEL_ARGS, bricks[item / ROWS_PER_BRICK]);
        const int lj = r % BRICK, lk = r / BRICK;
        if (lj < s.nj && lk < s.nk) sum = row_sum_squares(phi, rhs, g, LEVEL_ARGS, s, row_walk(phi, s, lj, lk, -1), coef);
    }
    sums[lid] = sum;
    barrier(CLK_LOCAL_MEM_FENCE);
    if (item < rows && r == 0) partial[item / ROWS_PER_BRICK] = brick_sum(sums + lid);
}
#endif
