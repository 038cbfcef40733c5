// One red-black Gauss-Seidel half sweep over the cells with (i + j + k) % 2 == color,
// over-relaxed by omega (exactly the Gauss-Seidel value when omega is 1). Cells of one
// colour read only the other colour, so the order inside a launch does not matter.
// No work-item reads what another writes (common.cl's PlaneWalk): of the rows other
// work-items own it loads only the other colour's lanes, and of its own it stores only
// the colour's lanes where another may read them. Every lane is computed and the
// colour's kept, which costs less than gathering them.

// The walk's row after the half sweep (its other lanes as they were).
ALWAYS_INLINE row_t swept_row(global const real* phi, global const real* rhs, global const real* g, LEVEL_PARAMS,
                              BrickSite s, PlaneWalk w, real coef, real omega) {
    const RowNeighbours n = plane_neighbours(phi, LEVEL_ARGS, s, w);
    const row_t a = load_row(g, w.at) * coef;
    const row_t gs = (load_row(rhs, w.at) + a * n.sum) / ((row_t)1 + a * n.count);
    const row_mask lane = (row_mask)(0, 1, 2, 3, 4, 5, 6, 7);
    const row_mask odd = (lane & (row_mask)1) != (row_mask)0, in = lane < (row_mask)(nx - s.i0);
    const int lanes = colour_lanes(s, w.lj, w.lk, w.color);
    return select(w.p, omega != (real)1 ? w.p + omega * (gs - w.p) : gs, (lanes ? odd : ~odd) & in);
}

// Stores the colour's lanes (those of parity `lanes`) of the first `inside`.
ALWAYS_INLINE void store_colour(global real* row, row_t v, int lanes, int inside) {
    if (inside == BRICK && lanes == 0) {
        row[0] = v.s0, row[2] = v.s2, row[4] = v.s4, row[6] = v.s6;
    } else if (inside == BRICK) {
        row[1] = v.s1, row[3] = v.s3, row[5] = v.s5, row[7] = v.s7;
    } else {  // a partial brick's
        real t[BRICK];
        vstore8(v, 0, t);
        for (int q = lanes; q < inside; q += 2) row[q] = t[q];
    }
}

#ifndef SNVR_ROW_KERNELS
// CPUs: one work-item per active brick, walking its planes: only its faces' rows (first
// and last along y and z) and its first and last lanes are read by others.
kernel void smooth(uint count, global real* phi, global const real* rhs, global const real* g,
                   global const uint* bricks, global const uint* slot, LEVEL_PARAMS, int color, real coef,
                   real omega) {
    const uint item = (uint)get_global_id(0);
    if (item >= count) return;
    const BrickSite s = brick_site(slot, LEVEL_ARGS, bricks[item]);
    const int inside = min(BRICK, nx - s.i0);  // lanes inside the grid
    for (int lk = 0; lk < s.nk; ++lk)
        for (PlaneWalk w = plane_walk(phi, s, lk, color); w.lj < s.nj; w = plane_step(phi, s, w)) {
            const row_t v = swept_row(phi, rhs, g, LEVEL_ARGS, s, w, coef, omega);
            const int lanes = colour_lanes(s, w.lj, lk, color);
            global real* row = phi + w.at;
            if (lk == 0 || lk == BRICK - 1 || w.lj == 0 || w.lj == BRICK - 1) {  // a face row
                store_colour(row, v, lanes, inside);
            } else {  // lanes 1-6 are this brick's alone; 0 and 7 only in the colour
                vstore2(v.s12, 0, row + 1);
                vstore4(v.s3456, 0, row + 3);
                if (lanes == 0) row[0] = v.s0;
                else if (inside == BRICK) row[BRICK - 1] = v.s7;
            }
        }
}

#else
// GPUs: one work-item per row (common.cl's row kernels), storing the colour's lanes.
kernel void smooth(uint rows, global real* phi, global const real* rhs, global const real* g,
                   global const uint* bricks, global const uint* slot, LEVEL_PARAMS, int color, real coef,
                   real omega) {
    const uint item = (uint)get_global_id(0);
    if (item >= rows) return;
    const BrickSite s = brick_site(slot, LEVEL_ARGS, bricks[item / ROWS_PER_BRICK]);
    const int r = (int)(item % ROWS_PER_BRICK), lj = r % BRICK, lk = r / BRICK;
    if (lj >= s.nj || lk >= s.nk) return;
    const PlaneWalk w = row_walk(phi, s, lj, lk, color);
    store_colour(phi + w.at, swept_row(phi, rhs, g, LEVEL_ARGS, s, w, coef, omega), colour_lanes(s, lj, lk, color),
                 min(BRICK, nx - s.i0));
}
#endif
