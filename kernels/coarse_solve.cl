// The coarsest level's exact solve: phi = M rhs on its coupled cells (M dense,
// column-major, from lib/src/coarse_inverse.cpp), each row summed over c ascending.
// One work-item per row; neighbouring work-items read neighbouring entries of a column.
kernel void coarse_solve(global const real* inverse, global const uint* cells, uint n,
                         global const real* rhs, global real* phi) {
    const uint r = (uint)get_global_id(0);
    if (r >= n) return;
    real s = (real)0;
    for (uint c = 0; c < n; ++c) s += inverse[(size_t)c * n + r] * rhs[cells[c]];
    phi[cells[r]] = s;
}
