// The operations of the split scheme and its multigrid, one call each. The time loop
// and the V-cycle schedule (multigrid.cpp, reconstruct.cpp) are written once against
// this interface and never know which backend runs them. Every operation visits the
// active bricks of its level only (see hierarchy.hpp).
//
// Fields per level: phi (solution / correction), rhs, g (coefficient). Level 0 phi is
// the phase field; on coarser levels phi is the correction. The operator on level l is
// A phi = phi - dt g Lap_h phi, 7-point Laplacian, mirror (Neumann) boundary.
#pragma once
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "solver/coarse_inverse.hpp"
#include "solver/hierarchy.hpp"
#include "solver/layout.hpp"

namespace snvr {

enum class FieldKind { phi, rhs, g, distance };

// Keeps the surface within a tube around the exact offset surface d = l: after each
// nonlinear step tanh((inner - d) s) <= phi <= tanh((outer - d) s) (normalised), i.e. phi
// lies between the initial profiles (s = 1 / (sqrt(2) xi)) of the surfaces d = inner and
// d = outer. Bounding every cell, not just the sign, is what holds the mesher's
// crossings (interpolated in atanh(phi)) on the right side of the tube's walls.
// The defaults (walls at -+1e30) switch it off.
template <class Real>
struct Tube {
    Real inner = -1e30f, outer = 1e30f, s = 1;
};

template <class Real>
class Backend {
public:
    virtual ~Backend() = default;
    virtual std::string name() const = 0;

    // Allocates every level's fields (zero, constant bricks filled) for this layout.
    virtual void setup(const BrickLayout& layout) = 0;
    virtual std::size_t bytes() const = 0;

    // Level 0, whole grid: phi = tanh((l - d) / (sqrt(2) xi)), g = 1 - phi^2 (eqs. 4-5),
    // and phi = sign(l - d), g = 0 where |l - d| > cut. `distance` is normalised and in
    // level 0's brick storage (BrickGrid::storage() values, pack_active); the backend
    // keeps it (FieldKind::distance, level 0) for the tube, adopting the vector where
    // it can (the host's backend), so that it is never held twice.
    virtual void init_phase(std::vector<Real> distance, Real offset, Real inv_sqrt2_xi, Real cut) = 0;
    // g on level+1: harmonic mean of the 8 children's g (0 if any child is 0).
    virtual void restrict_coefficient(int level) = 0;

    // Level 0: rhs = phi (the right-hand side of eq. 8 is phi^n).
    virtual void load_rhs() = 0;
    // One red-black Gauss-Seidel half sweep over cells with (i + j + k) % 2 == color,
    // over-relaxed: phi += omega (gs - phi), exactly phi = gs when omega is 1.
    virtual void smooth(int level, int color, Real dt_over_h2, Real omega) = 0;
    // Sum over the level of r^2, r = rhs - A phi (accumulated in double, brick order).
    virtual double residual_sum_squares(int level, Real dt_over_h2) = 0;
    // rhs(level+1) = g_c * mean(r / g) over the 8 children (0 where g_c = 0); phi(level+1) = 0.
    virtual void restrict_residual(int level, Real dt_over_h2) = 0;
    // phi(level) += prolongation of phi(level+1), only where g(level) > 0.
    virtual void prolong_correct(int level, bool trilinear) = 0;
    // The coarsest level's exact solve (coarse_inverse.hpp): the inverse is handed over
    // once per run; each solve sets phi = M rhs on its cells, in the order r, then c
    // ascending (the other cells keep phi = 0).
    virtual void set_coarse_inverse(int level, const CoarseInverse& inverse) = 0;
    virtual void coarse_solve(int level) = 0;

    // Level 0: phi = phi / sqrt(e + phi^2 (1 - e)), e = exp(-k g), k = 2 dt / eps^2 (eq. 11),
    // then held within the tube (where g > 0).
    virtual void nonlinear(Real k, const Tube<Real>& tube) = 0;

    // Copies between the level's fields and dense x-fastest arrays of its shape. Upload
    // writes the cells of active bricks only (the others hold constants); download reads all.
    // Returns once every operation asked for so far has finished (devices run them
    // asynchronously); for timings.
    virtual void finish() {}

    virtual void upload(int level, FieldKind field, const Real* dense) = 0;
    virtual void download(int level, FieldKind field, Real* dense) = 0;

    // The end of a run: frees every field but level 0's phi, then hands phi over in its
    // brick storage (BrickGrid::storage() values), so that the phase field never sits
    // beside a second copy of the solver's fields. Nothing runs on the backend after.
    virtual std::vector<Real> take_phase() = 0;
};

// The backend rule, in one place (backend_factory.cpp).
// make_backend: "auto" (an OpenCL GPU, else an OpenCL CPU, else OpenMP), "openmp",
// "opencl[:P:D]" or a device name substring. Throws ParameterError for a device that
// does not exist; under "auto" never fails (why OpenCL was passed over goes to `notes`).
template <class Real>
std::unique_ptr<Backend<Real>> make_backend(const std::string& device, std::vector<std::string>& notes);

// Sets the backend up on the layout. Under "auto", an OpenCL device too small for it
// hands over to the OpenMP backend (the host may hold it), with a note saying so.
template <class Real>
void setup_backend(std::unique_ptr<Backend<Real>>& backend, const std::string& device, const BrickLayout& layout,
                   std::vector<std::string>& notes);

}  // namespace snvr
