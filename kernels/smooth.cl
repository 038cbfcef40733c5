// One red-black Gauss-Seidel half sweep over the cells with (i + j + k) % 2 == color,
// over-relaxed by omega (exactly the Gauss-Seidel value when omega is 1). Cells of one
// colour read only the other colour, so the order inside a launch does not matter; a
// row is written whole, its other colour with the values it already holds.
// One work-item per row, 64 per brick.
kernel void smooth(global real* phi, global const real* rhs, global const real* g,
                   global const uint* bricks, global const uint* slot, LEVEL_PARAMS,
                   int color, real coef, real omega) {
    const Row w = brick_row(slot, bx, by, bricks[get_group_id(0)], (int)get_local_id(0));
    if (w.j >= ny || w.k >= nz) return;
    const row_t p = load_row(phi, w.at);
    const row_t a = load_row(g, w.at) * coef;
    const RowNeighbours n = row_neighbours(phi, slot, LEVEL_ARGS, w, p);
    const row_t gs = (load_row(rhs, w.at) + a * n.sum) / ((row_t)1 + a * n.count);
    const row_t relaxed = omega == (real)1 ? gs : p + omega * (gs - p);
    // Bricks start at even coordinates: lane q has the colour when (q + j + k) is.
    const int first = (w.j + w.k + color) & 1;
    const row_mask lane = (row_mask)(0, 1, 2, 3, 4, 5, 6, 7);
    const row_mask mine = ((lane & (row_mask)1) == (row_mask)first) & row_in_grid(w, nx);
    vstore8(select(p, relaxed, mine), 0, phi + w.at);
}
