#include "opencl/opencl_backend.hpp"

#include <algorithm>
#include <initializer_list>
#include <tuple>
#include <type_traits>
#include <vector>

#include "solver/brick_grid.hpp"
#include "opencl/runtime.hpp"
#include "opencl/work_groups.hpp"

namespace snvr {

namespace {

using opencl::guarded;

// Work shapes (kernels/common.cl): row kernels one work-item per row of a brick (64);
// the brick kernels (sweep, residual, restriction, prolongation) in the variant
// work_groups() chose: on CPUs one work-item per plane (8), the sweep one per brick, on
// GPUs one per row; restrict_coefficient one per coarse cell; in groups of the sizes
// work_groups() chose for the device.
constexpr std::size_t kRows = 64, kPlanes = 8, kRowCells = kBrickCells / kRows;

// The five ints kernels take as LEVEL_PARAMS.
struct Shape {
    cl_int nx, ny, nz, bx, by;
};

struct LevelBuffers {
    cl::Buffer phi, rhs, g;  // brick storage (brick_grid.hpp), constant bricks first
    cl::Buffer distance;     // level 0 only: the normalised distance (for the tube)
    cl::Buffer bricks, slot;  // active brick ids; slot of every brick
    std::size_t cells = 0;    // storage cells of each field
    std::size_t active = 0;   // active bricks
};

template <class Real>
class OpenCLBackend final : public Backend<Real> {
public:
    explicit OpenCLBackend(const std::string& spec) : OpenCLBackend(opencl::choose_device(spec)) {}

    explicit OpenCLBackend(const opencl::DeviceEntry& device)
        : groups_(opencl::work_groups(device, sizeof(Real))),
          rt_(device, std::is_same_v<Real, double> ? "double" : "float", groups_.build_options()),
          init_(rt_.kernel("init_phase")),
          restrict_coefficient_(rt_.kernel("restrict_coefficient")),
          smooth_(rt_.kernel("smooth")),
          residual_norm_(rt_.kernel("residual_norm")),
          sum_partials_(rt_.kernel("sum_partials")),
          restrict_residual_(rt_.kernel("restrict_residual")),
          prolong_(rt_.kernel("prolong_correct")),
          nonlinear_(rt_.kernel("nonlinear")),
          copy_(rt_.kernel("copy_bricks")),
          zero_(rt_.kernel("zero_field")),
          coarse_solve_(rt_.kernel("coarse_solve")) {
        // A kernel may allow less than the device (registers): the sizes not compiled in
        // shrink to fit; the compiled ones must fit as they are.
        const auto limit = [&](std::initializer_list<const cl::Kernel*> ks) {
            std::size_t n = rt_.device().max_group;
            for (const cl::Kernel* k : ks) n = std::min(n, rt_.kernel_group_limit(*k));
            return n;
        };
        groups_.rows = opencl::fit_group(groups_.rows, limit({&init_, &nonlinear_, &copy_, &zero_, &coarse_solve_}));
        groups_.bricks = opencl::fit_group(groups_.bricks, limit({&smooth_}));
        groups_.cells = opencl::fit_group(groups_.cells, limit({&restrict_coefficient_}));
        const std::size_t brick_group = rows_variant() ? groups_.brick_rows : groups_.planes;
        for (const auto& [k, name, size] : {std::tuple{&residual_norm_, "residual_norm", brick_group},
                                            std::tuple{&restrict_residual_, "restrict_residual", brick_group},
                                            std::tuple{&prolong_, "prolong_correct", brick_group},
                                            std::tuple{&sum_partials_, "sum_partials", groups_.reduce}})
            if (rt_.kernel_group_limit(*k) < size)
                throw ResourceError(std::string("OpenCL device '") + rt_.device().name + "' runs kernel " + name +
                                    " in work-groups of at most " + std::to_string(rt_.kernel_group_limit(*k)) +
                                    " work-items, under the " + std::to_string(size) +
                                    " it was built for; set SNVR_OPENCL_WORK_GROUP to a smaller power of two");
    }

    std::string name() const override {
        const opencl::DeviceEntry& d = rt_.device();
        return "opencl:" + std::to_string(d.platform) + ":" + std::to_string(d.index) + " (" + d.name + ", " + d.platform_name +
               "; " + groups_.describe() + ")";
    }

    void setup(const BrickLayout& layout) override {
        guarded("setup", [&] {
            const Hierarchy& hier = layout.hierarchy;
            hier_ = hier;
            grids_ = layout.grids;
            // Fail before allocating, with the sizes, rather than at the first launch.
            std::size_t need = 0;
            for (std::size_t l = 0; l < grids_.size(); ++l) need += (l == 0 ? 4 : 3) * grids_[l].storage() * sizeof(Real);
            const opencl::DeviceEntry& d = rt_.device();
            if (need > d.memory)
                throw ResourceError("the solver's fields need " + std::to_string(need >> 20) + " MiB on OpenCL device '" + d.name +
                                    "', which has " + std::to_string(d.memory >> 20) + " MiB; use a coarser --resolution or --device openmp");
            levels_.assign(hier.levels.size(), {});
            std::size_t most_bricks = 1;
            for (std::size_t l = 0; l < hier.levels.size(); ++l) {
                const Level& lv = hier.levels[l];
                LevelBuffers& b = levels_[l];
                b.cells = grids_[l].storage();
                b.active = lv.bricks.size();
                most_bricks = std::max(most_bricks, b.active);
                for (cl::Buffer* f : {&b.phi, &b.rhs, &b.g, &b.distance}) {
                    if (f == &b.distance && l > 0) continue;
                    if (f == &b.rhs && l == 0) continue;  // init_phase makes it, once the distance's host copy is gone
                    *f = zeroed_field(b.cells);
                }
                const std::vector<Real> plus(kBrickCells, Real(1)), minus(kBrickCells, Real(-1));
                rt_.queue().enqueueWriteBuffer(b.phi, CL_TRUE, kPlusSlot * kBrickCells * sizeof(Real), kBrickCells * sizeof(Real), plus.data());
                rt_.queue().enqueueWriteBuffer(b.phi, CL_TRUE, kMinusSlot * kBrickCells * sizeof(Real), kBrickCells * sizeof(Real), minus.data());
                b.bricks = rt_.buffer(lv.bricks.size() * sizeof(cl_uint), "the active brick list");
                if (!lv.bricks.empty())
                    rt_.queue().enqueueWriteBuffer(b.bricks, CL_TRUE, 0, lv.bricks.size() * sizeof(cl_uint), lv.bricks.data());
                b.slot = rt_.buffer(grids_[l].slot.size() * sizeof(cl_uint), "the brick slot table");
                write_slots(int(l));
            }
            partial_ = rt_.buffer(most_bricks * accumulator_size(), "residual partial sums");
            total_ = rt_.buffer(accumulator_size(), "residual sum");
        });
    }

    std::size_t bytes() const override {
        std::size_t n = 0;
        for (std::size_t l = 0; l < levels_.size(); ++l)
            n += (l == 0 ? 4 : 3) * levels_[l].cells * sizeof(Real) + (levels_[l].active + grids_[l].slot.size()) * sizeof(cl_uint);
        return n;
    }

    void init_phase(std::vector<Real> d, Real offset, Real s, Real cut) override {
        guarded("init_phase", [&] {
            LevelBuffers& b = levels_[0];
            if (b.active > 0) {
                rt_.queue().enqueueWriteBuffer(b.distance, CL_TRUE, 0, b.cells * sizeof(Real), d.data());
                launch_items(init_, b.active * kRows, groups_.rows, b.distance, b.phi, b.g, b.bricks, b.slot, shape(0), offset,
                             s, cut);
                rt_.queue().finish();
            }
            std::vector<Real>().swap(d);
            b.rhs = zeroed_field(b.cells);
        });
    }

    void restrict_coefficient(int level) override {
        guarded("restrict_coefficient", [&] {
            const LevelBuffers &f = levels_[std::size_t(level)], &c = levels_[std::size_t(level) + 1];
            launch_items(restrict_coefficient_, c.active * kBrickCells, groups_.cells, f.g, f.slot, shape(level), c.g,
                         c.bricks, c.slot, shape(level + 1));
        });
    }

    void load_rhs() override {
        guarded("load_rhs", [&] {
            const LevelBuffers& b = levels_[0];
            // A kernel over the active bricks: PoCL's clEnqueueCopyBuffer copied at half the rate.
            launch_items(copy_, b.active * kRows, groups_.rows, b.phi, b.rhs, b.bricks, b.slot);
        });
    }

    void smooth(int level, int color, Real c, Real omega) override {
        guarded("smooth", [&] {
            const LevelBuffers& b = levels_[std::size_t(level)];
            // A work-item per row on GPUs, per brick on CPUs (kernels/smooth.cl).
            const std::size_t items = rows_variant() ? b.active * kRows : b.active;
            launch_items(smooth_, items, rows_variant() ? groups_.rows : groups_.bricks, b.phi, b.rhs, b.g, b.bricks, b.slot,
                         shape(level), cl_int(color), c, omega);
        });
    }

    double residual_sum_squares(int level, Real c) override {
        return guarded("residual_sum_squares", [&] {
            const LevelBuffers& b = levels_[std::size_t(level)];
            if (b.active == 0) return 0.0;
            launch_bricks(residual_norm_, b.active, b.phi, b.rhs, b.g, b.bricks, b.slot, shape(level), c, partial_);
            launch(sum_partials_, groups_.reduce, groups_.reduce, partial_, cl_uint(b.active), total_);
            if (rt_.double_accumulator()) return read_scalar<double>();
            return double(read_scalar<float>());
        });
    }

    void restrict_residual(int level, Real c) override {
        guarded("restrict_residual", [&] {
            const LevelBuffers &f = levels_[std::size_t(level)], &cb = levels_[std::size_t(level) + 1];
            const Shape cs = shape(level + 1);
            launch_bricks(restrict_residual_, f.active, f.phi, f.rhs, f.g, f.bricks, f.slot, shape(level), c, cb.phi, cb.rhs,
                          cb.g, cb.slot, cs.bx, cs.by);
        });
    }

    void prolong_correct(int level, bool trilinear) override {
        guarded("prolong_correct", [&] {
            const LevelBuffers &f = levels_[std::size_t(level)], &cb = levels_[std::size_t(level) + 1];
            launch_bricks(prolong_, f.active, f.phi, f.g, f.bricks, f.slot, shape(level), cb.phi, cb.slot, shape(level + 1),
                          cl_int(trilinear));
        });
    }

    void set_coarse_inverse(int level, const CoarseInverse& inv) override {
        guarded("set_coarse_inverse", [&] {
            const std::vector<std::uint32_t> at = storage_positions(grids_[std::size_t(level)], inv.cells);
            const std::vector<Real> m(inv.matrix.begin(), inv.matrix.end());
            coarse_n_ = at.size();
            if (coarse_n_ == 0) return;  // nothing couples there: the solve leaves phi = 0
            coarse_cells_ = rt_.buffer(at.size() * sizeof(cl_uint), "the coarse cell list");
            coarse_matrix_ = rt_.buffer(m.size() * sizeof(Real), "the coarse inverse");
            rt_.queue().enqueueWriteBuffer(coarse_cells_, CL_TRUE, 0, at.size() * sizeof(cl_uint), at.data());
            rt_.queue().enqueueWriteBuffer(coarse_matrix_, CL_TRUE, 0, m.size() * sizeof(Real), m.data());
        });
    }

    void coarse_solve(int level) override {
        guarded("coarse_solve", [&] {
            const LevelBuffers& b = levels_[std::size_t(level)];
            launch(coarse_solve_, padded(coarse_n_, groups_.rows), groups_.rows, coarse_matrix_, coarse_cells_,
                   cl_uint(coarse_n_), b.rhs, b.phi);
        });
    }

    void nonlinear(Real k, const Tube<Real>& tube) override {
        guarded("nonlinear", [&] {
            const LevelBuffers& b = levels_[0];
            launch_items(nonlinear_, b.active * kRows, groups_.rows, b.phi, b.g, b.distance, b.bricks, b.slot, k,
                         tube.inner, tube.outer, tube.s);
        });
    }

    void upload(int level, FieldKind field, const Real* dense) override {
        guarded("upload", [&] {
            const LevelBuffers& b = levels_[std::size_t(level)];
            std::vector<Real> storage(b.cells, Real(0));
            pack_active(grids_[std::size_t(level)], hier_.levels[std::size_t(level)], dense, storage.data());
            // Active bricks follow the constant ones; the constants stay as they are.
            const std::size_t skip = kConstantSlots * kBrickCells;
            if (b.cells > skip)
                rt_.queue().enqueueWriteBuffer(buffer(level, field), CL_TRUE, skip * sizeof(Real), (b.cells - skip) * sizeof(Real),
                                               storage.data() + skip);
        });
    }

    void download(int level, FieldKind field, Real* dense) override {
        guarded("download", [&] {
            std::vector<Real> storage(levels_[std::size_t(level)].cells);
            rt_.queue().enqueueReadBuffer(buffer(level, field), CL_TRUE, 0, storage.size() * sizeof(Real), storage.data());
            unpack(grids_[std::size_t(level)], storage.data(), dense);
        });
    }

    std::vector<Real> take_phase() override {
        std::vector<Real> phi;
        guarded("take_phase", [&] {
            rt_.queue().finish();
            cl::Buffer kept = levels_[0].phi;
            levels_.clear();
            partial_ = total_ = cl::Buffer();
            phi.resize(grids_[0].storage());
            rt_.queue().enqueueReadBuffer(kept, CL_TRUE, 0, phi.size() * sizeof(Real), phi.data());
        });
        return phi;
    }

    void finish() override {
        guarded("finish", [&] { rt_.queue().finish(); });
    }

private:
    cl::Buffer zeroed_field(std::size_t cells) {
        cl::Buffer f = rt_.buffer(cells * sizeof(Real), "a solver field");
        static_assert(kBrickCells % kRowCells == 0, "a field is whole rows");
        launch_items(zero_, cells / kRowCells, groups_.rows, f);
        return f;
    }

    std::size_t accumulator_size() const { return rt_.double_accumulator() ? sizeof(double) : sizeof(float); }

    Shape shape(int level) const {
        const Level& lv = hier_.levels[std::size_t(level)];
        return {lv.nx, lv.ny, lv.nz, lv.bx, lv.by};
    }

    const cl::Buffer& buffer(int level, FieldKind field) const {
        const LevelBuffers& b = levels_[std::size_t(level)];
        switch (field) {
            case FieldKind::phi: return b.phi;
            case FieldKind::rhs: return b.rhs;
            case FieldKind::g: return b.g;
            case FieldKind::distance: break;
        }
        return b.distance;
    }

    void write_slots(int level) {
        const std::vector<std::uint32_t>& slot = grids_[std::size_t(level)].slot;
        rt_.queue().enqueueWriteBuffer(levels_[std::size_t(level)].slot, CL_TRUE, 0, slot.size() * sizeof(cl_uint), slot.data());
    }

    template <class T>
    T read_scalar() {
        T v{};
        rt_.queue().enqueueReadBuffer(total_, CL_TRUE, 0, sizeof(T), &v);
        return v;
    }

    static void set_args(cl::Kernel&, cl_uint) {}
    template <class... Rest>
    static void set_args(cl::Kernel& k, cl_uint i, const Shape& s, const Rest&... rest) {
        for (cl_int v : {s.nx, s.ny, s.nz, s.bx, s.by}) k.setArg(i++, v);
        set_args(k, i, rest...);
    }
    template <class T, class... Rest>
    static void set_args(cl::Kernel& k, cl_uint i, const T& v, const Rest&... rest) {
        k.setArg(i, v);
        set_args(k, i + 1, rest...);
    }

    // Sets the arguments in order and enqueues `global` work-items in groups of `local`.
    template <class... Args>
    void launch(cl::Kernel& k, std::size_t global, std::size_t local, const Args&... args) {
        if (global == 0) return;  // a level without active bricks
        set_args(k, 0, args...);
        rt_.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(global), cl::NDRange(local));
    }

    static std::size_t padded(std::size_t n, std::size_t group) { return (n + group - 1) / group * group; }

    // A kernel of `items` work-items (its first argument) in groups of `group`, the last padded.
    template <class... Args>
    void launch_items(cl::Kernel& k, std::size_t items, std::size_t group, const Args&... args) {
        launch(k, padded(items, group), group, cl_uint(items), args...);
    }

    bool rows_variant() const { return groups_.shape == opencl::KernelShape::Rows; }

    // A brick kernel over `active` bricks, in the device's variant: a work-item per plane
    // or per row.
    template <class... Args>
    void launch_bricks(cl::Kernel& k, std::size_t active, const Args&... args) {
        if (rows_variant()) launch_items(k, active * kRows, groups_.brick_rows, args...);
        else launch_items(k, active * kPlanes, groups_.planes, args...);
    }

    opencl::WorkGroups groups_;
    opencl::Runtime rt_;
    cl::Kernel init_, restrict_coefficient_, smooth_, residual_norm_, sum_partials_, restrict_residual_, prolong_, nonlinear_, copy_,
        zero_, coarse_solve_;
    Hierarchy hier_;
    std::vector<BrickGrid> grids_;
    std::vector<LevelBuffers> levels_;
    cl::Buffer partial_, total_;
    cl::Buffer coarse_matrix_, coarse_cells_;
    std::size_t coarse_n_ = 0;
};

}  // namespace

template <class Real>
std::unique_ptr<Backend<Real>> make_opencl_backend(const std::string& spec) {
    return opencl::guarded("backend", [&] { return std::unique_ptr<Backend<Real>>(std::make_unique<OpenCLBackend<Real>>(spec)); });
}

template std::unique_ptr<Backend<double>> make_opencl_backend<double>(const std::string&);
template std::unique_ptr<Backend<float>> make_opencl_backend<float>(const std::string&);

}  // namespace snvr
