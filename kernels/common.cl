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

// Row kernels: one work-item per row of 8 cells along x (64 per brick; their first
// argument is the number of rows, the last group padded), the row as one vector, so
// CPUs get whole SIMD registers and GPUs contiguous 64-byte accesses per work-item.
#ifdef SNVR_DOUBLE
typedef double8 row_t;
typedef long8 row_mask;      // select() needs an integer vector of the same width
#else
typedef float8 row_t;
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

// Sum of the six neighbours of each cell of the row, in the order -x +x -y +y -z +z,
// 0 outside the grid, and how many lie inside it.
typedef struct {
    row_t sum, count;
} RowNeighbours;

// Lanes of the row inside the grid (a partial brick's last row is shorter).
ALWAYS_INLINE row_mask row_in_grid(Row w, int nx) {
    return (row_mask)(0, 1, 2, 3, 4, 5, 6, 7) < (row_mask)(nx - w.i0);
}

// Plane kernels: one work-item per plane (lk) of a brick, 8 per brick and
// PLANES_PER_GROUP (a multiple of 8, set by the host from the device's limits: 64 unless
// they allow less or SNVR_OPENCL_WORK_GROUP asks) per work-group, walking the plane's
// rows along y with the y neighbours carried in registers: the brick's place and
// neighbours are found once per plane, not per row, and no row just written is read
// back (PoCL: sweeps 1.4x faster than an item per row). Their first argument is the
// number of planes (8 per active brick): the last group is padded.
#ifndef PLANES_PER_GROUP
#define PLANES_PER_GROUP 64
#endif
#ifndef REDUCE_GROUP
#define REDUCE_GROUP 256
#endif

// The same operations with a work-item per row (64 per brick, neighbouring work-items on
// neighbouring rows, so a GPU's warp reads contiguous memory): the variant the host
// builds for GPUs (-DSNVR_ROW_KERNELS: each operation's file defines one variant of its
// kernel, under the same name). ROWS_PER_GROUP: a multiple of 64 (whole bricks).
#ifndef ROWS_PER_GROUP
#define ROWS_PER_GROUP 256
#endif
#define BRICKS_PER_ROW_GROUP (ROWS_PER_GROUP / ROWS_PER_BRICK)

// A brick's place and where its six neighbours are stored (its own storage where a
// neighbour lies outside the grid; the has_ flags say which).
typedef struct {
    int i0, j0, k0;  // grid position of the first cell
    int nj, nk;      // rows inside the grid along y and z
    size_t at;       // storage index of the first cell
    size_t xm, xp, ym, yp, zm, zp;
    bool has_xm, has_xp, has_ym, has_yp, has_zm, has_zp;
} BrickSite;

ALWAYS_INLINE BrickSite brick_site(global const uint* slot, LEVEL_PARAMS, uint b) {
    BrickSite s;
    s.i0 = (int)(b % (uint)bx) * BRICK;
    s.j0 = (int)(b / (uint)bx % (uint)by) * BRICK;
    s.k0 = (int)(b / ((uint)bx * (uint)by)) * BRICK;
    s.nj = min(BRICK, ny - s.j0);
    s.nk = min(BRICK, nz - s.k0);
    s.at = (size_t)slot[b] * BRICK_CELLS;
    const uint sy = (uint)bx, sz = (uint)bx * (uint)by;
    s.has_xm = s.i0 > 0;
    s.has_xp = s.i0 + BRICK < nx;
    s.has_ym = s.j0 > 0;
    s.has_yp = s.j0 + BRICK < ny;
    s.has_zm = s.k0 > 0;
    s.has_zp = s.k0 + BRICK < nz;
    s.xm = s.has_xm ? (size_t)slot[b - 1] * BRICK_CELLS : s.at;
    s.xp = s.has_xp ? (size_t)slot[b + 1] * BRICK_CELLS : s.at;
    s.ym = s.has_ym ? (size_t)slot[b - sy] * BRICK_CELLS : s.at;
    s.yp = s.has_yp ? (size_t)slot[b + sy] * BRICK_CELLS : s.at;
    s.zm = s.has_zm ? (size_t)slot[b - sz] * BRICK_CELLS : s.at;
    s.zp = s.has_zp ? (size_t)slot[b + sz] * BRICK_CELLS : s.at;
    return s;
}

// A walk along y through plane lk of a brick: row lj and its y neighbours. Kernels that
// write a row may carry the values loaded before the write: they read only lanes of
// the neighbour rows that no work of the launch changes.
//
// A kernel that writes some lanes of its rows while others read them (the red-black
// sweep, color >= 0) loads of the rows other work-items own ("foreign": those of other
// bricks when a work-item has a whole brick, every other row when it has one row) only
// the lanes of the other colour, the ones it needs and no one writes: no work-item reads
// what another writes in the same launch. color < 0: whole rows (read-only kernels).
typedef struct {
    int lj, lk;
    int color;          // the sweep's colour, or -1
    bool one_row;       // the work-item owns this row only (else its whole brick)
    size_t at;          // storage index of row lj
    row_t ym, p, yp;    // rows lj - 1, lj, lj + 1 (0 outside the grid)
} PlaneWalk;

// Which lanes of row (lj, lk) have the sweep's colour (bricks start at even
// coordinates): the odd ones (1) or the even ones (0); -1 for every lane.
ALWAYS_INLINE int colour_lanes(BrickSite s, int lj, int lk, int color) {
    return color < 0 ? -1 : (s.j0 + lj + s.k0 + lk + color) & 1;
}

// A foreign row: whole, or only the lanes of parity `lanes` (0 in the others).
ALWAYS_INLINE row_t load_foreign(global const real* p, size_t at, int lanes) {
    if (lanes < 0) return load_row(p, at);
    global const real* q = p + at + lanes;
    const real a = q[0], b = q[2], c = q[4], d = q[6];
    return lanes ? (row_t)((real)0, a, (real)0, b, (real)0, c, (real)0, d)
                 : (row_t)(a, (real)0, b, (real)0, c, (real)0, d, (real)0);
}

ALWAYS_INLINE row_t row_after(global const real* p, BrickSite s, int lj, int lk, int color, bool one_row) {
    const size_t at = s.at + (size_t)(BRICK * (lj + BRICK * lk));
    const int lanes = colour_lanes(s, lj, lk, color);
    return lj + 1 < s.nj ? (one_row ? load_foreign(p, at + BRICK, lanes) : load_row(p, at + BRICK))
           : s.has_yp    ? load_foreign(p, s.yp + (size_t)(BRICK * BRICK * lk), lanes)
                         : (row_t)0;
}

// Row (lj, lk) alone, for kernels with a work-item per row.
ALWAYS_INLINE PlaneWalk row_walk(global const real* p, BrickSite s, int lj, int lk, int color) {
    PlaneWalk w;
    w.lj = lj;
    w.lk = lk;
    w.color = color;
    w.one_row = true;
    w.at = s.at + (size_t)(BRICK * (lj + BRICK * lk));
    const int lanes = colour_lanes(s, lj, lk, color);
    w.ym = lj > 0      ? load_foreign(p, w.at - BRICK, lanes)
           : s.has_ym ? load_foreign(p, s.ym + (size_t)(BRICK * (BRICK - 1 + BRICK * lk)), lanes)
                      : (row_t)0;
    w.p = load_row(p, w.at);
    w.yp = row_after(p, s, lj, lk, color, true);
    return w;
}

ALWAYS_INLINE PlaneWalk plane_walk(global const real* p, BrickSite s, int lk, int color) {
    PlaneWalk w;
    w.lj = 0;
    w.lk = lk;
    w.color = color;
    w.one_row = false;
    w.at = s.at + (size_t)(BRICK * BRICK * lk);
    w.ym = s.has_ym ? load_foreign(p, s.ym + (size_t)(BRICK * (BRICK - 1 + BRICK * lk)), colour_lanes(s, 0, lk, color))
                    : (row_t)0;
    w.p = load_row(p, w.at);
    w.yp = row_after(p, s, 0, lk, color, false);
    return w;
}

ALWAYS_INLINE PlaneWalk plane_step(global const real* p, BrickSite s, PlaneWalk w) {
    w.ym = w.p;
    w.p = w.yp;
    ++w.lj;
    w.at += BRICK;
    if (w.lj < s.nj) w.yp = row_after(p, s, w.lj, w.lk, w.color, false);
    return w;
}

// The neighbour sum and count of the walk's row.
ALWAYS_INLINE RowNeighbours plane_neighbours(global const real* p, LEVEL_PARAMS, BrickSite s, PlaneWalk w) {
    const size_t in_brick = (size_t)(BRICK * (w.lj + BRICK * w.lk));
    const int lanes = colour_lanes(s, w.lj, w.lk, w.color);
    // The x neighbours beyond the row: read where lane 0 (7) is wanted.
    const real xm = s.has_xm && lanes <= 0 ? p[s.xm + in_brick + (BRICK - 1)] : (real)0;
    const real xp = s.has_xp && lanes != 0 ? p[s.xp + in_brick] : (real)0;
    const int inner = w.one_row ? lanes : -1;  // the lanes to load of this brick's other rows
    const row_t zm = w.lk > 0 ? load_foreign(p, w.at - BRICK * BRICK, inner)
                     : s.has_zm ? load_foreign(p, s.zm + (size_t)(BRICK * (w.lj + BRICK * (BRICK - 1))), lanes)
                                : (row_t)0;
    const row_t zp = w.lk + 1 < s.nk ? load_foreign(p, w.at + BRICK * BRICK, inner)
                     : s.has_zp      ? load_foreign(p, s.zp + (size_t)(BRICK * w.lj), lanes)
                                     : (row_t)0;
    const row_t left = (row_t)(xm, w.p.s0123, w.p.s456);
    const row_t right = (row_t)(w.p.s1234, w.p.s567, xp);
    RowNeighbours n;
    n.sum = ((((left + right) + w.ym) + w.yp) + zm) + zp;
    const int j = s.j0 + w.lj, k = s.k0 + w.lk;
    const int yz = 6 - (j == 0) - (j + 1 >= ny) - (k == 0) - (k + 1 >= nz);
    if (s.has_xm && s.has_xp) {  // nearly every brick: no x edge
        n.count = (row_t)(real)yz;
    } else {
        real count[BRICK];
        for (int q = 0; q < BRICK; ++q) count[q] = (real)(yz - (s.i0 + q == 0) - (s.i0 + q + 1 >= nx));
        n.count = vload8(0, count);
    }
    return n;
}

// r = rhs - A phi on the walk's row, A phi = phi - coef g Lap phi (coef = dt / h^2).
ALWAYS_INLINE row_t plane_residual(global const real* phi, global const real* rhs, global const real* g, LEVEL_PARAMS,
                                   BrickSite s, PlaneWalk w, real coef) {
    const row_t a = load_row(g, w.at) * coef;
    const RowNeighbours n = plane_neighbours(phi, LEVEL_ARGS, s, w);
    return (load_row(rhs, w.at) - w.p) + a * (n.sum - n.count * w.p);
}

// Lanes of a brick's rows inside the grid.
ALWAYS_INLINE row_mask lanes_in_grid(BrickSite s, int nx) {
    return (row_mask)(0, 1, 2, 3, 4, 5, 6, 7) < (row_mask)(nx - s.i0);
}

// exp and tanh on rows: phase_math.h over row_t, the operations the OpenMP backend
// runs per cell (lib/src/solver/phase_math.hpp), so the same bits. The embedder splices
// the header in place of the #include: the program needs no file at run time.
#define PM_REAL row_t
#define PM_SCALAR real
#ifdef SNVR_DOUBLE
#define PM_DOUBLE 1
#define PM_BITS as_long8  // to row_mask, the integer row
#define PM_FROM_BITS as_double8
#else
#define PM_DOUBLE 0
#define PM_BITS as_int8
#define PM_FROM_BITS as_float8
#endif
#define PM_PARTS RowExp
#define PM_INLINE ALWAYS_INLINE
#define PM_AT_LEAST fmax
#include "phase_math.h"
