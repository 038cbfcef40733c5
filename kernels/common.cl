// Shared by every kernel (prepended to the program, not an operation of its own): the
// scalar types, the sparse brick-major layout of lib/src/brick_grid.hpp, and the 7-point
// stencil with exactly the OpenMP backend's arithmetic: absent neighbours add 0 and drop
// out of the count, neighbours summed in the order -x +x -y +y -z +z, no contraction
// into FMA. Built with -DREAL=double|float and -DACC (the reduction type).
#pragma OPENCL FP_CONTRACT OFF
#ifdef SNVR_FP64
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#endif

// The helpers below must dissolve into their kernels: PoCL otherwise calls them,
// passing vectors through memory (2x slower sweeps).
#define ALWAYS_INLINE inline __attribute__((always_inline))

typedef REAL real;
typedef ACC acc;

#define BRICK 8
#define BRICK_CELLS 512

// A level's shape: cells per axis and bricks along x and y.
#define LEVEL_PARAMS int nx, int ny, int nz, int bx, int by
#define LEVEL_ARGS nx, ny, nz, bx, by

typedef struct {
    int i, j, k;  // grid position
    size_t at;    // storage index
} Cell;

ALWAYS_INLINE size_t cell_index(global const uint* slot, int bx, int by, int i, int j, int k) {
    const uint b = (uint)(i / BRICK) + (uint)bx * ((uint)(j / BRICK) + (uint)by * (uint)(k / BRICK));
    return (size_t)slot[b] * BRICK_CELLS + (size_t)(i % BRICK + BRICK * (j % BRICK + BRICK * (k % BRICK)));
}

// Cell q of brick b.
ALWAYS_INLINE Cell brick_cell(global const uint* slot, int bx, int by, uint b, int q) {
    Cell c;
    c.i = (int)(b % (uint)bx) * BRICK + q % BRICK;
    c.j = (int)(b / (uint)bx % (uint)by) * BRICK + q / BRICK % BRICK;
    c.k = (int)(b / ((uint)bx * (uint)by)) * BRICK + q / (BRICK * BRICK);
    c.at = (size_t)slot[b] * BRICK_CELLS + (size_t)q;
    return c;
}

ALWAYS_INLINE bool in_grid(LEVEL_PARAMS, int i, int j, int k) {
    return i >= 0 && j >= 0 && k >= 0 && i < nx && j < ny && k < nz;
}

// Row kernels: one work-item per row of 8 cells along x (64 per brick, one brick per
// work-group of 64), the row as one vector, so CPUs get whole SIMD registers and GPUs
// contiguous 64-byte accesses per work-item.
#ifdef SNVR_DOUBLE
typedef double8 row_t;
typedef double4 half_row_t;  // the cells of one colour in a row
typedef long8 row_mask;      // select() needs an integer vector of the same width
#else
typedef float8 row_t;
typedef float4 half_row_t;
typedef int8 row_mask;
#endif
#define ROWS_PER_BRICK 64

ALWAYS_INLINE row_t load_row(global const real* p, size_t at) { return vload8(0, p + at); }

typedef struct {
    uint b;               // brick id
    int i0, j, k;         // grid position of the row's first cell
    int lj, lk;           // row position inside the brick
    size_t at;            // storage index of the row's first cell
} Row;

ALWAYS_INLINE Row brick_row(global const uint* slot, int bx, int by, uint b, int r) {
    Row w;
    w.b = b;
    w.lj = r % BRICK;
    w.lk = r / BRICK;
    w.i0 = (int)(b % (uint)bx) * BRICK;
    w.j = (int)(b / (uint)bx % (uint)by) * BRICK + w.lj;
    w.k = (int)(b / ((uint)bx * (uint)by)) * BRICK + w.lk;
    w.at = (size_t)slot[b] * BRICK_CELLS + (size_t)(BRICK * r);
    return w;
}

// Row (lj, lk) of another brick.
ALWAYS_INLINE row_t row_of(global const real* p, global const uint* slot, uint brick, int lj, int lk) {
    return load_row(p, (size_t)slot[brick] * BRICK_CELLS + (size_t)(BRICK * (lj + BRICK * lk)));
}

// Sum of the six neighbours of each cell of the row, in the order -x +x -y +y -z +z,
// 0 outside the grid, and how many lie inside it.
typedef struct {
    row_t sum, count;
} RowNeighbours;

ALWAYS_INLINE RowNeighbours row_neighbours(global const real* p, global const uint* slot, LEVEL_PARAMS, Row w, row_t self) {
    const uint sy = (uint)bx, sz = (uint)bx * (uint)by;
    const size_t in_row = (size_t)(BRICK * (w.lj + BRICK * w.lk));
    const real xm = w.i0 > 0 ? p[(size_t)slot[w.b - 1] * BRICK_CELLS + in_row + (BRICK - 1)] : (real)0;
    const real xp = w.i0 + BRICK < nx ? p[(size_t)slot[w.b + 1] * BRICK_CELLS + in_row] : (real)0;
    const row_t zero = (row_t)0;
    const row_t ym = w.j == 0 ? zero : w.lj > 0 ? load_row(p, w.at - BRICK) : row_of(p, slot, w.b - sy, BRICK - 1, w.lk);
    const row_t yp = w.j + 1 >= ny ? zero : w.lj + 1 < BRICK ? load_row(p, w.at + BRICK) : row_of(p, slot, w.b + sy, 0, w.lk);
    const row_t zm = w.k == 0 ? zero : w.lk > 0 ? load_row(p, w.at - BRICK * BRICK) : row_of(p, slot, w.b - sz, w.lj, BRICK - 1);
    const row_t zp = w.k + 1 >= nz ? zero : w.lk + 1 < BRICK ? load_row(p, w.at + BRICK * BRICK) : row_of(p, slot, w.b + sz, w.lj, 0);
    const row_t left = (row_t)(xm, self.s0123, self.s456);
    const row_t right = (row_t)(self.s1234, self.s567, xp);
    RowNeighbours n;
    n.sum = ((((left + right) + ym) + yp) + zm) + zp;
    const int yz = 6 - (w.j == 0) - (w.j + 1 >= ny) - (w.k == 0) - (w.k + 1 >= nz);
    if (w.i0 > 0 && w.i0 + BRICK < nx) {  // nearly every row: no x edge
        n.count = (row_t)(real)yz;
    } else {
        real count[BRICK];
        for (int q = 0; q < BRICK; ++q) count[q] = (real)(yz - (w.i0 + q == 0) - (w.i0 + q + 1 >= nx));
        n.count = vload8(0, count);
    }
    return n;
}

// Lanes of the row inside the grid (a partial brick's last row is shorter).
ALWAYS_INLINE row_mask row_in_grid(Row w, int nx) {
    return (row_mask)(0, 1, 2, 3, 4, 5, 6, 7) < (row_mask)(nx - w.i0);
}

// r = rhs - A phi on a row, A phi = phi - coef g Lap phi (coef = dt / h^2).
ALWAYS_INLINE row_t row_residual(global const real* phi, global const real* rhs, global const real* g,
                          global const uint* slot, LEVEL_PARAMS, Row w, real coef) {
    const row_t p = load_row(phi, w.at);
    const row_t a = load_row(g, w.at) * coef;
    const RowNeighbours n = row_neighbours(phi, slot, LEVEL_ARGS, w, p);
    return (load_row(rhs, w.at) - p) + a * (n.sum - n.count * p);
}

// exp and tanh on rows, the same operations in the same order as
// lib/src/solver/phase_math.hpp (see there): bit-identical to the OpenMP backend.
#ifdef SNVR_DOUBLE
#define AS_ROW_BITS as_long8  // to row_mask, the integer row
#define AS_ROW as_double8
#define EXP_LOWEST -708.0
#define EXP_ROUND 6755399441055744.0
#define EXP_LOG2E 1.4426950408889634
#define EXP_LN2_HI 6.93147180369123816490e-01
#define EXP_LN2_LO 1.90821492927058770002e-10
#define EXP_MANTISSA 52
#define EXP_BIAS 1023
#else
#define AS_ROW_BITS as_int8
#define AS_ROW as_float8
#define EXP_LOWEST -87.0f
#define EXP_ROUND 12582912.0f
#define EXP_LOG2E 1.44269502f
#define EXP_LN2_HI 6.9314575195e-01f
#define EXP_LN2_LO 1.4286067653e-06f
#define EXP_MANTISSA 23
#define EXP_BIAS 127
#endif

// (e^r - 1) / r by Horner on 1/k!.
ALWAYS_INLINE row_t expm1_over_r(row_t r) {
#ifdef SNVR_DOUBLE
    row_t p = (row_t)(1.0 / 6227020800.0);
    p = p * r + 1.0 / 479001600.0;
    p = p * r + 1.0 / 39916800.0;
    p = p * r + 1.0 / 3628800.0;
    p = p * r + 1.0 / 362880.0;
    p = p * r + 1.0 / 40320.0;
    p = p * r + 1.0 / 5040.0;
    p = p * r + 1.0 / 720.0;
    p = p * r + 1.0 / 120.0;
    p = p * r + 1.0 / 24.0;
    p = p * r + 1.0 / 6.0;
    p = p * r + 0.5;
    return p * r + 1.0;
#else
    row_t p = (row_t)(1.0f / 5040.0f);
    p = p * r + 1.0f / 720.0f;
    p = p * r + 1.0f / 120.0f;
    p = p * r + 1.0f / 24.0f;
    p = p * r + 1.0f / 6.0f;
    p = p * r + 0.5f;
    return p * r + 1.0f;
#endif
}

// e^x = s (1 + q) for x <= 0, s = 2^n.
typedef struct {
    row_t s, q;
} RowExp;

ALWAYS_INLINE RowExp exp_parts(row_t x) {
    x = fmax(x, (real)EXP_LOWEST);
    const row_t shifted = x * (real)EXP_LOG2E + (real)EXP_ROUND;
    const row_t n = shifted - (real)EXP_ROUND;
    const row_t r = (x - n * (real)EXP_LN2_HI) - n * (real)EXP_LN2_LO;
    RowExp e;
    e.s = AS_ROW((AS_ROW_BITS(shifted) - AS_ROW_BITS((row_t)(real)EXP_ROUND) + EXP_BIAS) << EXP_MANTISSA);
    e.q = r * expm1_over_r(r);
    return e;
}

ALWAYS_INLINE row_t exp_nonpositive(row_t x) {
    const RowExp e = exp_parts(x);
    return e.s + e.s * e.q;
}

ALWAYS_INLINE row_t tanh_of(row_t y) {
    const RowExp e = exp_parts((real)-2 * fabs(y));
    const row_t m = (e.s - (real)1) + e.s * e.q;
    const row_t t = ((real)0 - m) / ((real)2 + m);
    return select(t, -t, y < (real)0);
}
