// Fine residual to the coarse right-hand side: rhs_c = g_c * mean(r / g) over the 8
// children (order dk, dj, di), 0 where g_c = 0; the coarse correction starts at 0.
// One work-group of 64 per active fine brick: each work-item computes a row's residual,
// then one of the brick's 4x4x4 coarse cells. A fine brick's children fill a block of
// one coarse brick, so groups write disjoint coarse cells.
kernel void restrict_residual(global const real* phi, global const real* rhs, global const real* g,
                              global const uint* bricks, global const uint* slot, LEVEL_PARAMS, real coef,
                              global real* phi_coarse, global real* rhs_coarse, global const real* g_coarse,
                              global const uint* slot_coarse, int cbx, int cby) {
    local real res[BRICK_CELLS];
    const int lid = (int)get_local_id(0);
    const Row w = brick_row(slot, bx, by, bricks[get_group_id(0)], lid);
    const row_t r = w.j < ny && w.k < nz ? row_residual(phi, rhs, g, slot, LEVEL_ARGS, w, coef) : (row_t)0;
    vstore8(r, lid, res);
    barrier(CLK_LOCAL_MEM_FENCE);
    const int ci = lid % 4, cj = lid / 4 % 4, ck = lid / 16;
    const int j0 = w.j - w.lj, k0 = w.k - w.lk;
    if (w.i0 + 2 * ci >= nx || j0 + 2 * cj >= ny || k0 + 2 * ck >= nz) return;
    const size_t n = cell_index(slot_coarse, cbx, cby, w.i0 / 2 + ci, j0 / 2 + cj, k0 / 2 + ck);
    phi_coarse[n] = (real)0;
    const real gc = g_coarse[n];
    if (gc == (real)0) {
        rhs_coarse[n] = (real)0;
        return;
    }
    const size_t base = w.at - (size_t)(BRICK * lid);
    real sum = (real)0;
    for (int dk = 0; dk < 2; ++dk)
        for (int dj = 0; dj < 2; ++dj)
            for (int di = 0; di < 2; ++di) {
                const int loc = (2 * ci + di) + BRICK * ((2 * cj + dj) + BRICK * (2 * ck + dk));
                sum += res[loc] / g[base + (size_t)loc];
            }
    rhs_coarse[n] = gc * (sum * (real)0.125);
}
