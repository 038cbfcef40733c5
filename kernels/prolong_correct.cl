// phi += prolongation of the coarse correction, only where g > 0. Cell-centred
// trilinear: 3/4 on the parent, 1/4 on the next coarse cell towards the child, coarse
// indices clamped at the grid edge (mirror), applied x first, then y, then z; or
// injection. One work-item per fine row, 64 per brick.

// A fine row's x interpolation from coarse row (J, K): its 4 parents and one coarse cell
// of halo on each side, clamped.
inline row_t along_x(global const real* pc, global const uint* slot, int cnx, int cbx, int cby, int I0, int J, int K,
                     int trilinear) {
    real c[6];
    for (int t = 0; t < 6; ++t) c[t] = pc[cell_index(slot, cbx, cby, clamp(I0 - 1 + t, 0, cnx - 1), J, K)];
    const row_t parent = (row_t)(c[1], c[1], c[2], c[2], c[3], c[3], c[4], c[4]);
    if (!trilinear) return parent;
    const row_t next = (row_t)(c[0], c[2], c[1], c[3], c[2], c[4], c[3], c[5]);
    return (real)0.75 * parent + (real)0.25 * next;
}

kernel void prolong_correct(global real* phi, global const real* g, global const uint* bricks,
                            global const uint* slot, LEVEL_PARAMS, global const real* phi_coarse,
                            global const uint* slot_coarse, int cnx, int cny, int cnz, int cbx, int cby,
                            int trilinear) {
    const Row w = brick_row(slot, bx, by, bricks[get_group_id(0)], (int)get_local_id(0));
    if (w.j >= ny || w.k >= nz) return;
    const int I0 = w.i0 / 2, J = w.j >> 1, K = w.k >> 1;
    row_t correction;
    if (!trilinear) {
        correction = along_x(phi_coarse, slot_coarse, cnx, cbx, cby, I0, J, K, 0);
    } else {
        const int J2 = clamp(J + ((w.j & 1) ? 1 : -1), 0, cny - 1);
        const int K2 = clamp(K + ((w.k & 1) ? 1 : -1), 0, cnz - 1);
        const real w0 = (real)0.75, w1 = (real)0.25;
        const row_t plane_k = w0 * along_x(phi_coarse, slot_coarse, cnx, cbx, cby, I0, J, K, 1) +
                              w1 * along_x(phi_coarse, slot_coarse, cnx, cbx, cby, I0, J2, K, 1);
        const row_t plane_k2 = w0 * along_x(phi_coarse, slot_coarse, cnx, cbx, cby, I0, J, K2, 1) +
                               w1 * along_x(phi_coarse, slot_coarse, cnx, cbx, cby, I0, J2, K2, 1);
        correction = w0 * plane_k + w1 * plane_k2;
    }
    const row_t p = load_row(phi, w.at);
    const row_mask live = load_row(g, w.at) != (row_t)0;  // g is 0 outside the grid too
    vstore8(select(p, p + correction, live), 0, phi + w.at);
}
