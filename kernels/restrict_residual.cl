// Fine residual to the coarse right-hand side: rhs_c = g_c * mean(r / g) over the 8
// children (order dk, dj, di), 0 where g_c = 0; the coarse correction starts at 0.
// The work-items of a brick leave its residual rows in local memory, then compute its
// 4x4x4 coarse cells. A fine brick's children fill a block of one coarse brick, so
// bricks write disjoint coarse cells.

// Coarse cell c (0-63, x fastest) of the fine brick at s, from its residuals.
ALWAYS_INLINE void restrict_cell(int c, BrickSite s, local const real* brick_res, global const real* g, LEVEL_PARAMS,
                                 global real* phi_coarse, global real* rhs_coarse, global const real* g_coarse,
                                 global const uint* slot_coarse, int cbx, int cby) {
    const int ci = c % 4, cj = c / 4 % 4, ck = c / 16;
    if (s.i0 + 2 * ci >= nx || s.j0 + 2 * cj >= ny || s.k0 + 2 * ck >= nz) return;
    const size_t n = cell_index(slot_coarse, cbx, cby, s.i0 / 2 + ci, s.j0 / 2 + cj, s.k0 / 2 + ck);
    phi_coarse[n] = (real)0;
    const real gc = g_coarse[n];
    if (gc == (real)0) {
        rhs_coarse[n] = (real)0;
        return;
    }
    real sum = (real)0;
    for (int dk = 0; dk < 2; ++dk)
        for (int dj = 0; dj < 2; ++dj)
            for (int di = 0; di < 2; ++di) {
                const int loc = (2 * ci + di) + BRICK * ((2 * cj + dj) + BRICK * (2 * ck + dk));
                sum += brick_res[loc] / g[s.at + (size_t)loc];
            }
    rhs_coarse[n] = gc * (sum * (real)0.125);
}

#ifndef SNVR_ROW_KERNELS
// CPUs: a plane kernel (common.cl); each plane's item computes 8 coarse cells.
kernel void restrict_residual(uint planes, global const real* phi, global const real* rhs, global const real* g,
                              global const uint* bricks, global const uint* slot, LEVEL_PARAMS, real coef,
                              global real* phi_coarse, global real* rhs_coarse, global const real* g_coarse,
                              global const uint* slot_coarse, int cbx, int cby) {
    local real res[PLANES_PER_GROUP / BRICK * BRICK_CELLS];
    const uint item = (uint)get_global_id(0);
    const int lid = (int)get_local_id(0), lk = lid % BRICK;
    local real* brick_res = res + BRICK_CELLS * (lid / BRICK);
    BrickSite s;
    if (item < planes) {
        s = brick_site(slot, LEVEL_ARGS, bricks[item / BRICK]);
        int lj = 0;
        if (lk < s.nk)
            for (PlaneWalk w = plane_walk(phi, s, lk, -1); w.lj < s.nj; w = plane_step(phi, s, w), ++lj)
                vstore8(plane_residual(phi, rhs, g, LEVEL_ARGS, s, w, coef), lj + BRICK * lk, brick_res);
        for (; lj < BRICK; ++lj) vstore8((row_t)0, lj + BRICK * lk, brick_res);  // rows outside the grid
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    if (item >= planes) return;
    for (int c = BRICK * lk; c < BRICK * (lk + 1); ++c)
        restrict_cell(c, s, brick_res, g, LEVEL_ARGS, phi_coarse, rhs_coarse, g_coarse, slot_coarse, cbx, cby);
}

#else
// GPUs: a work-item per row, then one per coarse cell.
kernel void restrict_residual(uint rows, global const real* phi, global const real* rhs, global const real* g,
                              global const uint* bricks, global const uint* slot, LEVEL_PARAMS, real coef,
                              global real* phi_coarse, global real* rhs_coarse, global const real* g_coarse,
                              global const uint* slot_coarse, int cbx, int cby) {
    local real res[BRICKS_PER_ROW_GROUP * BRICK_CELLS];
    const uint item = (uint)get_global_id(0);
    const int lid = (int)get_local_id(0), r = lid % ROWS_PER_BRICK;
    local real* brick_res = res + BRICK_CELLS * (lid / ROWS_PER_BRICK);
    BrickSite s;
    if (item < rows) {
        s = brick_site(slot, LEVEL_ARGS, bricks[item / ROWS_PER_BRICK]);
        const int lj = r % BRICK, lk = r / BRICK;
        row_t v = (row_t)0;  // rows outside the grid
        if (lj < s.nj && lk < s.nk) v = plane_residual(phi, rhs, g, LEVEL_ARGS, s, row_walk(phi, s, lj, lk, -1), coef);
        vstore8(v, r, brick_res);
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    if (item >= rows) return;
    restrict_cell(r, s, brick_res, g, LEVEL_ARGS, phi_coarse, rhs_coarse, g_coarse, slot_coarse, cbx, cby);
}
#endif
