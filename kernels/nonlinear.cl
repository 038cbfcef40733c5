// The exact nonlinear step (eq. 11): phi = phi / sqrt(e + phi^2 (1 - e)), e = exp(-k g),
// k = 2 dt / eps^2; nothing to do where g = 0 (e = 1). Then the tube (backend.hpp):
// tanh((inner - d) s) <= phi <= tanh((outer - d) s).
// One work-item per cell.
kernel void nonlinear(global real* phi, global const real* g, global const real* distance,
                      global const uint* bricks, global const uint* slot, real k, real inner,
                      real outer, real s) {
    const size_t id = get_global_id(0);
    const size_t n = (size_t)slot[bricks[id / BRICK_CELLS]] * BRICK_CELLS + id % BRICK_CELLS;
    const real gn = g[n];
    if (gn == (real)0) return;
    const real e = exp(-k * gn);
    const real p = phi[n];
    real q = p / sqrt(e + p * p * ((real)1 - e));
    const real d = distance[n];
    q = fmin(fmax(q, tanh((inner - d) * s)), tanh((outer - d) * s));
    phi[n] = q;
}
