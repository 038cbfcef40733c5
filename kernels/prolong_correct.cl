// phi += prolongation of the coarse correction, only where g > 0. Cell-centred
// trilinear: 3/4 on the parent, 1/4 on the next coarse cell towards the child, coarse
// indices clamped at the grid edge (mirror), applied x first, then y, then z; or
// injection. The work-items of a brick load its 4x4x4 coarse parents and a one-cell halo
// to local memory, then correct their rows.
#define HALO 6  // coarse cells per axis around a fine brick

// A fine row's x interpolation from halo row (jj, kk).
ALWAYS_INLINE row_t along_x(local const real* cv, int jj, int kk, int trilinear) {
    local const real* c = cv + HALO * (jj + HALO * kk);
    const row_t parent = (row_t)(c[1], c[1], c[2], c[2], c[3], c[3], c[4], c[4]);
    if (!trilinear) return parent;
    const row_t next = (row_t)(c[0], c[2], c[1], c[3], c[2], c[4], c[3], c[5]);
    return (real)0.75 * parent + (real)0.25 * next;
}

// Halo row t (0-35: J = t % 6, K = t / 6) of the fine brick at s.
ALWAYS_INLINE void load_halo_row(local real* cv, int t, BrickSite s, global const real* phi_coarse,
                                 global const uint* slot_coarse, int cnx, int cny, int cnz, int cbx, int cby) {
    // Halo origin in coarse cells: one before the brick's first parent. A halo row's
    // four middle cells (the parents) lie in one coarse brick: one load unless clamped.
    const int I0 = s.i0 / 2 - 1, J0 = s.j0 / 2 - 1, K0 = s.k0 / 2 - 1;
    const int J = clamp(J0 + t % HALO, 0, cny - 1), K = clamp(K0 + t / HALO, 0, cnz - 1);
    local real* row = cv + HALO * t;
    row[0] = phi_coarse[cell_index(slot_coarse, cbx, cby, max(I0, 0), J, K)];
    if (I0 + 4 < cnx) {
        vstore4(vload4(0, phi_coarse + cell_index(slot_coarse, cbx, cby, I0 + 1, J, K)), 0, row + 1);
    } else {
        for (int q = 1; q < HALO - 1; ++q) row[q] = phi_coarse[cell_index(slot_coarse, cbx, cby, min(I0 + q, cnx - 1), J, K)];
    }
    row[HALO - 1] = phi_coarse[cell_index(slot_coarse, cbx, cby, min(I0 + HALO - 1, cnx - 1), J, K)];
}

// Row (lj, lk) of the fine brick at s corrected where g > 0.
ALWAYS_INLINE void correct_row(global real* phi, global const real* g, local const real* cv, BrickSite s, int lj, int lk,
                               int trilinear) {
    const int k = s.k0 + lk;
    const int K = (k >> 1) - (s.k0 / 2 - 1), K2 = K + ((k & 1) ? 1 : -1);
    const size_t at = s.at + (size_t)(BRICK * (lj + BRICK * lk));
    const int j = s.j0 + lj;
    const int J = (j >> 1) - (s.j0 / 2 - 1);
    row_t correction;
    if (!trilinear) {
        correction = along_x(cv, J, K, 0);
    } else {
        const int J2 = J + ((j & 1) ? 1 : -1);
        const real w0 = (real)0.75, w1 = (real)0.25;
        const row_t plane_k = w0 * along_x(cv, J, K, 1) + w1 * along_x(cv, J2, K, 1);
        const row_t plane_k2 = w0 * along_x(cv, J, K2, 1) + w1 * along_x(cv, J2, K2, 1);
        correction = w0 * plane_k + w1 * plane_k2;
    }
    const row_t p = load_row(phi, at);
    const row_mask live = load_row(g, at) != (row_t)0;  // g is 0 outside the grid too
    vstore8(select(p, p + correction, live), 0, phi + at);
}

#ifndef SNVR_ROW_KERNELS
// CPUs: a plane kernel (common.cl).
kernel void prolong_correct(uint planes, global real* phi, global const real* g, global const uint* bricks,
                            global const uint* slot, LEVEL_PARAMS, global const real* phi_coarse,
                            global const uint* slot_coarse, int cnx, int cny, int cnz, int cbx, int cby,
                            int trilinear) {
    local real halo[PLANES_PER_GROUP / BRICK * HALO * HALO * HALO];
    const uint item = (uint)get_global_id(0);
    const int lid = (int)get_local_id(0), lk = lid % BRICK;
    local real* cv = halo + HALO * HALO * HALO * (lid / BRICK);
    BrickSite s;
    if (item < planes) {
        s = brick_site(slot, LEVEL_ARGS, bricks[item / BRICK]);
        for (int t = lk; t < HALO * HALO; t += BRICK) load_halo_row(cv, t, s, phi_coarse, slot_coarse, cnx, cny, cnz, cbx, cby);
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    if (item >= planes || lk >= s.nk) return;
    for (int lj = 0; lj < s.nj; ++lj) correct_row(phi, g, cv, s, lj, lk, trilinear);
}

#else
// GPUs: a work-item per row.
kernel void prolong_correct(uint rows, global real* phi, global const real* g, global const uint* bricks,
                            global const uint* slot, LEVEL_PARAMS, global const real* phi_coarse,
                            global const uint* slot_coarse, int cnx, int cny, int cnz, int cbx, int cby,
                            int trilinear) {
    local real halo[BRICKS_PER_ROW_GROUP * HALO * HALO * HALO];
    const uint item = (uint)get_global_id(0);
    const int lid = (int)get_local_id(0), r = lid % ROWS_PER_BRICK;
    local real* cv = halo + HALO * HALO * HALO * (lid / ROWS_PER_BRICK);
    BrickSite s;
    if (item < rows) {
        s = brick_site(slot, LEVEL_ARGS, bricks[item / ROWS_PER_BRICK]);
        if (r < HALO * HALO) load_halo_row(cv, r, s, phi_coarse, slot_coarse, cnx, cny, cnz, cbx, cby);
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    const int lj = r % BRICK, lk = r / BRICK;
    if (item >= rows || lj >= s.nj || lk >= s.nk) return;
    correct_row(phi, g, cv, s, lj, lk, trilinear);
}
#endif
