// g on the coarse level: harmonic mean of the 8 children's g, 0 if any child is 0
// (children summed in the order dk, dj, di). One work-item per coarse cell of the
// active bricks (`cells` of them; the last group padded).
kernel void restrict_coefficient(uint cells, global const real* g_fine, global const uint* slot_fine, LEVEL_PARAMS,
                                 global real* g_coarse, global const uint* bricks_coarse,
                                 global const uint* slot_coarse, int cnx, int cny, int cnz, int cbx, int cby) {
    const size_t id = get_global_id(0);
    if (id >= cells) return;
    const Cell c = brick_cell(slot_coarse, cbx, cby, bricks_coarse[id / BRICK_CELLS], (int)(id % BRICK_CELLS));
    if (!in_grid(cnx, cny, cnz, cbx, cby, c.i, c.j, c.k)) return;
    real sum = (real)0;
    bool zero = false;
    for (int dk = 0; dk < 2; ++dk)
        for (int dj = 0; dj < 2; ++dj)
            for (int di = 0; di < 2; ++di) {
                const real v = g_fine[cell_index(slot_fine, bx, by, 2 * c.i + di, 2 * c.j + dj, 2 * c.k + dk)];
                if (v == (real)0) zero = true;
                else sum += (real)1 / v;
            }
    g_coarse[c.at] = zero ? (real)0 : (real)8 / sum;
}
