// One red-black Gauss-Seidel half sweep over the cells with (i + j + k) % 2 == color,
// over-relaxed by omega (exactly the Gauss-Seidel value when omega is 1). Cells of one
// colour read only the other colour, so the order inside a launch does not matter; a
// row is written whole, its other colour with the values it already holds.
// A plane kernel (common.cl); every lane is computed and the colour's lanes kept, which
// costs less than gathering them.
kernel void smooth(uint planes, global real* phi, global const real* rhs, global const real* g,
                   global const uint* bricks, global const uint* slot, LEVEL_PARAMS, int color, real coef,
                   real omega) {
    const uint item = (uint)get_global_id(0);
    if (item >= planes) return;
    const BrickSite s = brick_site(slot, LEVEL_ARGS, bricks[item / BRICK]);
    const int lk = (int)(item % BRICK);
    if (lk >= s.nk) return;
    const row_mask inside = lanes_in_grid(s, nx);
    const row_mask odd = ((row_mask)(0, 1, 2, 3, 4, 5, 6, 7) & (row_mask)1) != (row_mask)0;
    const row_mask odd_lanes = odd & inside, even_lanes = ~odd & inside;
    const bool relax = omega != (real)1;
    for (PlaneWalk w = plane_walk(phi, s, lk); w.lj < s.nj; w = plane_step(phi, s, w)) {
        const RowNeighbours n = plane_neighbours(phi, LEVEL_ARGS, s, w);
        // Bricks start at even coordinates: lane q has the colour when (q + j + k + color) is even.
        const row_mask mine = ((s.j0 + w.lj + s.k0 + lk + color) & 1) ? odd_lanes : even_lanes;
        const row_t a = load_row(g, w.at) * coef;
        const row_t gs = (load_row(rhs, w.at) + a * n.sum) / ((row_t)1 + a * n.count);
        const row_t v = relax ? w.p + omega * (gs - w.p) : gs;
        vstore8(select(w.p, v, mine), 0, phi + w.at);
    }
}
