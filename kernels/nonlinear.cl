// The exact nonlinear step (eq. 11): phi = phi / sqrt(e + phi^2 (1 - e)), e = exp(-k g),
// k = 2 dt / eps^2; nothing to do where g = 0 (e = 1). Then the tube (backend.hpp):
// tanh((inner - d) s) <= phi <= tanh((outer - d) s). exp and tanh: common.cl's.
// A row kernel (common.cl).
kernel void nonlinear(uint rows, global real* phi, global const real* g, global const real* distance,
                      global const uint* bricks, global const uint* slot, real k, real inner,
                      real outer, real s) {
    const uint item = (uint)get_global_id(0);
    if (item >= rows) return;
    const size_t at = (size_t)slot[bricks[item / ROWS_PER_BRICK]] * BRICK_CELLS + BRICK * (item % ROWS_PER_BRICK);
    const row_t gn = load_row(g, at);
    const row_mask frozen = gn == (real)0;
    if (all(frozen)) return;  // most rows of a band's edge
    const row_t p = load_row(phi, at);
    const row_t e = exp_nonpositive(-k * gn);
    row_t q = p / sqrt(e + p * p * ((real)1 - e));
    const row_t d = load_row(distance, at);
    q = fmin(fmax(q, tanh_of((inner - d) * s)), tanh_of((outer - d) * s));
    vstore8(select(q, p, frozen), 0, phi + at);
}
