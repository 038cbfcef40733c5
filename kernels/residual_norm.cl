// Partial sums of r^2, one per active brick, in the OpenMP backend's order: each row's
// cells in x order, then the rows (y fastest, then z). A plane kernel (common.cl): each
// item leaves its rows' sums in local memory, the brick's first plane adds them up;
// rows and cells outside the grid add exact zeros.
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
        if (lk < s.nk) {
            for (PlaneWalk w = plane_walk(phi, s, lk); w.lj < s.nj; w = plane_step(phi, s, w)) {
                real r[BRICK];
                vstore8(plane_residual(phi, rhs, g, LEVEL_ARGS, s, w, coef), 0, r);
                acc sum = (acc)0;
                for (int q = 0; q < BRICK && s.i0 + q < nx; ++q) sum += (acc)r[q] * (acc)r[q];
                mine[w.lj] = sum;
            }
        }
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    if (item < planes && lk == 0) {
        acc total = (acc)0;
        for (int t = 0; t < ROWS_PER_BRICK; ++t) total += mine[t];
        partial[item / BRICK] = total;
    }
}
