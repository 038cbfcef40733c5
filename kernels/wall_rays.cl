// The check's walls (lib/src/check/walls.hpp): from each vertex along its inward normal,
// the distance to the first triangle met, ignoring the vertex's own triangles. Each
// work-item casts one ray through the host's TriangleGrid (mesh/triangle_grid.hpp: its
// cells' item lists and each item's box near its cell in bytes) as TriangleGrid::first_hit
// does: the same cells in the same order (the walk in double), the same float box filter a
// group of four items at a time (SSE's maxps and minps are `a > b ? a : b` and
// `a < b ? a : b`), the same exact test in double, no contraction into FMA (common.cl):
// the same wall to the bit. Double precision only: a device without it measures none.
#ifdef SNVR_FP64

#define WALL_BOX_STEPS 128
#define WALL_BOX_LOW 64
#define WALL_FLOAT_SLACK 9.5367431640625e-07  // 2^-20
#define WALL_GROUP 4

// The host's vec3 arithmetic, term by term in its order (not the builtins, which may fuse).
ALWAYS_INLINE double wall_dot(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
ALWAYS_INLINE void wall_cross(const double a[3], const double b[3], double out[3]) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

// Where origin + t dir meets triangle (a, b, c), widened by `slack` in its barycentric
// coordinates; -infinity where it does not (mesh/triangle_grid.cpp's ray_triangle).
ALWAYS_INLINE double wall_ray_triangle(const double o[3], const double dir[3], const double a[3], const double b[3],
                                       const double c[3], double slack) {
    double e1[3], e2[3], tv[3], pv[3], qv[3];
    for (int d = 0; d < 3; ++d) {
        e1[d] = b[d] - a[d];
        e2[d] = c[d] - a[d];
        tv[d] = o[d] - a[d];
    }
    wall_cross(dir, e2, pv);
    const double det = wall_dot(e1, pv);
    if (det == 0) return -INFINITY;
    const double inv = 1 / det;
    const double u = wall_dot(tv, pv) * inv;
    if (u < -slack || u > 1 + slack) return -INFINITY;
    wall_cross(tv, e1, qv);
    const double v = wall_dot(dir, qv) * inv;
    if (v < -slack || u + v > 1 + slack) return -INFINITY;
    return wall_dot(e2, qv) * inv;
}

// floor(x) clamped to [0, n - 1] (NaN gives 0).
ALWAYS_INLINE int wall_clamp_cell(double x, int n) {
    if (!(x > 0)) return 0;
    if (x >= (double)(n - 1)) return n - 1;
    return (int)x;
}

ALWAYS_INLINE void wall_vertex(global const double* xyz, uint v, double out[3]) {
    for (int d = 0; d < 3; ++d) out[d] = xyz[3 * (size_t)v + (size_t)d];
}

// walls[k]: the wall of vertex order[k], k < count (infinity where nothing is met or the
// normal vanishes). The grid: its low corner, cell edge and inverse, the boxes' margin in
// cells, cells per axis; start[c] .. start[c + 1] are cell c's items, the six planes of
// `boxes` `stride` bytes apart.
kernel void wall_rays(uint count, global const uint* order, global const double* vertices, global const uint* triangles,
                      global const double* normals, global const uint* start, global const uint* items,
                      global const uchar* boxes, ulong stride, double lo_x, double lo_y, double lo_z, double size,
                      double inv_size, double margin, int nx, int ny, int nz, double t_min, global double* walls) {
    const uint k = (uint)get_global_id(0);
    if (k >= count) return;
    const uint vertex = order[k];
    double o[3], nrm[3], dir[3], inv[3];
    wall_vertex(vertices, vertex, o);
    wall_vertex(normals, vertex, nrm);
    double best = INFINITY;
    if (wall_dot(nrm, nrm) == 0) {
        walls[k] = best;
        return;
    }
    for (int d = 0; d < 3; ++d) {
        dir[d] = -nrm[d];
        inv[d] = 1 / dir[d];
    }
    const double lo[3] = {lo_x, lo_y, lo_z};
    const int n[3] = {nx, ny, nz};
    // The ray as the boxes see it (TriangleGrid::RayBoxes).
    bool down[3];
    double o_cells[3];
    float box_inv[3];
    ulong near_plane[3], far_plane[3];
    for (int d = 0; d < 3; ++d) {
        down[d] = dir[d] < 0;
        o_cells[d] = (o[d] - lo[d]) * inv_size;
        double b = size * inv[d] / WALL_BOX_STEPS;
        if (!(fabs(b) <= 1e30)) b = down[d] ? -1e30 : 1e30;
        box_inv[d] = (float)b;
        near_plane[d] = (ulong)(down[d] ? 3 + d : d) * stride;
        far_plane[d] = (ulong)(down[d] ? d : 3 + d) * stride;
    }
    const float ta0 = convert_float_rtn(t_min);
    float tb = INFINITY;
    // The walk (TriangleGrid::walk): clipped to the grid's box, then cell by cell.
    double t0 = 0, t1 = INFINITY;
    bool misses = false;  // the box, along an axis the ray keeps
    for (int d = 0; d < 3; ++d) {
        const double box_lo = lo[d], box_hi = lo[d] + n[d] * size;
        if (dir[d] == 0) {
            misses |= o[d] < box_lo || o[d] > box_hi;
            continue;
        }
        double a = (box_lo - o[d]) * inv[d], b = (box_hi - o[d]) * inv[d];
        if (a > b) {
            const double s = a;
            a = b;
            b = s;
        }
        t0 = t0 < a ? a : t0;
        t1 = b < t1 ? b : t1;
    }
    if (!misses && !(t0 > t1)) {
        int c[3], step[3];
        double t_next[3], t_delta[3];
        for (int d = 0; d < 3; ++d) {
            c[d] = wall_clamp_cell((o[d] + t0 * dir[d] - lo[d]) * inv_size, n[d]);
            if (dir[d] > 0) {
                step[d] = 1;
                t_next[d] = (lo[d] + (c[d] + 1) * size - o[d]) * inv[d];
                t_delta[d] = size * inv[d];
            } else if (dir[d] < 0) {
                step[d] = -1;
                t_next[d] = (lo[d] + c[d] * size - o[d]) * inv[d];
                t_delta[d] = -size * inv[d];
            } else {
                step[d] = 0;
                t_next[d] = t_delta[d] = INFINITY;
            }
        }
        for (;;) {
            const int d = t_next[0] < t_next[1] ? (t_next[0] < t_next[2] ? 0 : 2) : (t_next[1] < t_next[2] ? 1 : 2);
            const size_t cell = (size_t)c[0] + (size_t)nx * ((size_t)c[1] + (size_t)ny * (size_t)c[2]);
            const uint first = start[cell], last = start[cell + 1];
            if (first != last) {
                // The boxes seen from this cell (RayBoxes::move_to).
                double reach = 256, steps[3];
                for (int a = 0; a < 3; ++a) {
                    steps[a] = (o_cells[a] - c[a]) * WALL_BOX_STEPS + WALL_BOX_LOW;
                    reach = reach < fabs(steps[a]) ? fabs(steps[a]) : reach;
                }
                const double m = margin * WALL_BOX_STEPS + reach * WALL_FLOAT_SLACK;
                float near_o[3], far_o[3];
                for (int a = 0; a < 3; ++a) {
                    near_o[a] = (float)(down[a] ? steps[a] - m : steps[a] + m);
                    far_o[a] = (float)(down[a] ? steps[a] + m : steps[a] - m);
                }
                for (uint g = first; g < last; g += WALL_GROUP) {
                    // A group's items dismissed by their boxes against the hit so far, then
                    // the rest tested exactly in turn.
                    uint pass = 0;
                    for (uint q = 0; q < WALL_GROUP && g + q < last; ++q) {
                        float ta = ta0, tq = tb;
                        for (int a = 0; a < 3; ++a) {
                            const float x = ((float)boxes[near_plane[a] + g + q] - near_o[a]) * box_inv[a];
                            const float y = ((float)boxes[far_plane[a] + g + q] - far_o[a]) * box_inv[a];
                            ta = ta > x ? ta : x;
                            tq = tq < y ? tq : y;
                        }
                        if (ta <= tq) pass |= 1u << q;
                    }
                    for (uint q = 0; q < WALL_GROUP; ++q) {
                        if (!(pass >> q & 1)) continue;
                        const uint tri = items[g + q];
                        const uint i0 = triangles[3 * (size_t)tri], i1 = triangles[3 * (size_t)tri + 1],
                                   i2 = triangles[3 * (size_t)tri + 2];
                        if (i0 == vertex || i1 == vertex || i2 == vertex) continue;
                        double pa[3], pb[3], pc[3];
                        wall_vertex(vertices, i0, pa);
                        wall_vertex(vertices, i1, pb);
                        wall_vertex(vertices, i2, pc);
                        const double s = wall_ray_triangle(o, dir, pa, pb, pc, 1e-9);
                        if (s > t_min && s < best) {
                            best = s;
                            tb = convert_float_rtp(s);
                        }
                    }
                }
                // A hit beyond this cell may still be beaten by one in a later cell.
                if (!(best > t_next[d])) break;
            }
            c[d] += step[d];
            if (c[d] < 0 || c[d] >= n[d] || t_next[d] > t1) break;
            t_next[d] += t_delta[d];
        }
    }
    walls[k] = best;
}

#endif
