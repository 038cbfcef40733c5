// Level 0, active bricks: phi = tanh((l - d) s), g = 1 - phi^2 (eqs. 4-5), and
// phi = sign(l - d), g = 0 beyond the cut. `distance` is packed like the fields.
// One work-item per cell.
kernel void init_phase(global const real* distance, global real* phi, global real* g,
                       global const uint* bricks, global const uint* slot, LEVEL_PARAMS,
                       real offset, real s, real cut) {
    const size_t id = get_global_id(0);
    const Cell c = brick_cell(slot, bx, by, bricks[id / BRICK_CELLS], (int)(id % BRICK_CELLS));
    if (!in_grid(LEVEL_ARGS, c.i, c.j, c.k)) return;
    const real diff = offset - distance[c.at];
    if (fabs(diff) > cut) {
        phi[c.at] = diff > (real)0 ? (real)1 : (real)-1;
        g[c.at] = (real)0;
    } else {
        const real p = tanh(diff * s);
        phi[c.at] = p;
        g[c.at] = (real)1 - p * p;
    }
}
