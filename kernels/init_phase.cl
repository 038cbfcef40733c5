// Level 0, active bricks: phi = tanh((l - d) s), g = 1 - phi^2 (eqs. 4-5), and
// phi = sign(l - d), g = 0 beyond the cut. `distance` is packed like the fields; tanh is
// common.cl's. A row kernel (common.cl); cells outside the grid keep their 0.
kernel void init_phase(uint rows, global const real* distance, global real* phi, global real* g,
                       global const uint* bricks, global const uint* slot, LEVEL_PARAMS,
                       real offset, real s, real cut) {
    const uint item = (uint)get_global_id(0);
    if (item >= rows) return;
    const Row w = brick_row(slot, bx, by, bricks[item / ROWS_PER_BRICK], (int)(item % ROWS_PER_BRICK));
    if (w.j >= ny || w.k >= nz) return;
    const row_t diff = offset - load_row(distance, w.at);
    const row_t p = tanh_of(diff * s);
    const row_mask beyond = fabs(diff) > cut;
    const row_t sign = select((row_t)(real)-1, (row_t)(real)1, diff > (real)0);
    const row_mask inside = row_in_grid(w, nx);
    vstore8(select(load_row(phi, w.at), select(p, sign, beyond), inside), 0, phi + w.at);
    vstore8(select(load_row(g, w.at), select((real)1 - p * p, (row_t)(real)0, beyond), inside), 0, g + w.at);
}
