// One red-black Gauss-Seidel half sweep over the cells with (i + j + k) % 2 == color,
// over-relaxed by omega (exactly the Gauss-Seidel value when omega is 1). Cells of one
// colour read only the other colour, so the order inside a launch does not matter; a
// row is written whole, its other colour with the values it already holds.
// One work-item per row, 64 per brick; the update runs on the row's four cells of the
// colour only (half the divisions).

// The four lanes of the colour: even lanes when `odd` is 0, odd lanes otherwise.
ALWAYS_INLINE half_row_t lanes(row_t v, int odd) { return odd ? v.odd : v.even; }

kernel void smooth(global real* phi, global const real* rhs, global const real* g,
                   global const uint* bricks, global const uint* slot, LEVEL_PARAMS,
                   int color, real coef, real omega) {
    const Row w = brick_row(slot, bx, by, bricks[get_group_id(0)], (int)get_local_id(0));
    if (w.j >= ny || w.k >= nz) return;
    const row_t p = load_row(phi, w.at);
    const RowNeighbours n = row_neighbours(phi, slot, LEVEL_ARGS, w, p);
    // Bricks start at even coordinates: lane q has the colour when (q + j + k + color) is even.
    const int odd = (w.j + w.k + color) & 1;
    const half_row_t a = lanes(load_row(g, w.at), odd) * coef;
    const half_row_t old = lanes(p, odd);
    const half_row_t gs = (lanes(load_row(rhs, w.at), odd) + a * lanes(n.sum, odd)) / ((half_row_t)1 + a * lanes(n.count, odd));
    const half_row_t v = omega == (real)1 ? gs : old + omega * (gs - old);
    const row_t merged = odd ? (row_t)(p.s0, v.s0, p.s2, v.s1, p.s4, v.s2, p.s6, v.s3)
                             : (row_t)(v.s0, p.s1, v.s1, p.s3, v.s2, p.s5, v.s3, p.s7);
    vstore8(select(p, merged, row_in_grid(w, nx)), 0, phi + w.at);
}
