// Field: dense values into shared bricks, and back.
#include "snvr/field.hpp"

#include <algorithm>
#include <cstring>
#include <map>
#include <type_traits>
#include <utility>

#include "snvr/error.hpp"

namespace snvr {
namespace {

// The bricks of dense x-fastest `values`; a brick whose in-grid cells are all one value
// (bit for bit) shares the stored brick of the first such brick, so a mostly uniform
// grid costs little.
template <class Real>
std::vector<Real> brick_values(const Field& f, const std::vector<Real>& values, std::vector<std::uint32_t>& table) {
    const int bx = f.bricks_x(), by = f.bricks_y(), bz = f.bricks_z();
    std::vector<Real> stored;
    std::map<std::uint64_t, std::uint32_t> uniform;  // a value's bits -> its stored brick
    table.assign(f.brick_count(), 0);
    Real cells[Field::kBrickCells];
    for (int kb = 0; kb < bz; ++kb)
        for (int jb = 0; jb < by; ++jb)
            for (int ib = 0; ib < bx; ++ib) {
                std::fill_n(cells, Field::kBrickCells, Real(0));
                bool same = true;
                const Real first = values[std::size_t(ib) * Field::kBrick +
                                          std::size_t(f.nx) * (std::size_t(jb) * Field::kBrick +
                                                               std::size_t(f.ny) * std::size_t(kb) * Field::kBrick)];
                for (int lk = 0; lk < Field::kBrick && kb * Field::kBrick + lk < f.nz; ++lk)
                    for (int lj = 0; lj < Field::kBrick && jb * Field::kBrick + lj < f.ny; ++lj)
                        for (int li = 0; li < Field::kBrick && ib * Field::kBrick + li < f.nx; ++li) {
                            const int i = ib * Field::kBrick + li, j = jb * Field::kBrick + lj, k = kb * Field::kBrick + lk;
                            const Real v = values[std::size_t(i) + std::size_t(f.nx) * (std::size_t(j) + std::size_t(f.ny) * std::size_t(k))];
                            cells[li + Field::kBrick * (lj + Field::kBrick * lk)] = v;
                            same = same && std::memcmp(&v, &first, sizeof v) == 0;
                        }
                const std::size_t b = std::size_t(ib) + std::size_t(bx) * (std::size_t(jb) + std::size_t(by) * std::size_t(kb));
                std::uint64_t key = 0;
                std::memcpy(&key, &first, sizeof first);
                if (same) {
                    const auto found = uniform.find(key);
                    if (found != uniform.end()) {
                        table[b] = found->second;
                        continue;
                    }
                    std::fill_n(cells, Field::kBrickCells, first);
                    uniform.emplace(key, std::uint32_t(stored.size() / Field::kBrickCells));
                }
                table[b] = std::uint32_t(stored.size() / Field::kBrickCells);
                stored.insert(stored.end(), cells, cells + Field::kBrickCells);
            }
    return stored;
}

}  // namespace

template <class Real>
Field Field::make(int nx, int ny, int nz, const std::vector<Real>& values, Precision precision) {
    if (nx < 0 || ny < 0 || nz < 0) throw ParameterError("Field::from_dense: negative grid size");
    Field f = shaped(nx, ny, nz, precision, {});
    if (values.size() != f.size())
        throw ParameterError("Field::from_dense: " + std::to_string(values.size()) + " values for a " +
                             std::to_string(nx) + "x" + std::to_string(ny) + "x" + std::to_string(nz) + " grid");
    if (f.size() == 0) {
        f.brick_.assign(f.brick_count(), 0);
        return f;
    }
    if constexpr (std::is_same_v<Real, float>) {
        f.f32_ = brick_values(f, values, f.brick_);
    } else if (precision == Precision::Double) {
        f.f64_ = brick_values(f, values, f.brick_);
    } else {
        f.f32_ = brick_values(f, std::vector<float>(values.begin(), values.end()), f.brick_);
    }
    return f;
}

Field Field::from_dense(int nx, int ny, int nz, const std::vector<double>& values, Precision precision) {
    return make(nx, ny, nz, values, precision);
}

Field Field::from_dense(int nx, int ny, int nz, const std::vector<float>& values) {
    return make(nx, ny, nz, values, Precision::Single);
}

Field Field::from_bricks(int nx, int ny, int nz, std::vector<std::uint32_t> table, std::vector<double> stored) {
    Field f = shaped(nx, ny, nz, Precision::Double, std::move(table));
    f.f64_ = std::move(stored);
    f.validate("Field::from_bricks: ");
    return f;
}

Field Field::from_bricks(int nx, int ny, int nz, std::vector<std::uint32_t> table, std::vector<float> stored) {
    Field f = shaped(nx, ny, nz, Precision::Single, std::move(table));
    f.f32_ = std::move(stored);
    f.validate("Field::from_bricks: ");
    return f;
}

Field Field::shaped(int nx, int ny, int nz, Precision precision, std::vector<std::uint32_t> table) {
    Field f;
    f.nx = nx;
    f.ny = ny;
    f.nz = nz;
    f.precision = precision;
    f.brick_ = std::move(table);
    return f;
}

std::vector<double> Field::to_dense() const {
    std::vector<double> out(size());
#pragma omp parallel for schedule(static)
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i)
                out[std::size_t(i) + std::size_t(nx) * (std::size_t(j) + std::size_t(ny) * std::size_t(k))] = at(i, j, k);
    return out;
}

void Field::validate(const std::string& who) const {
    if (nx < 0 || ny < 0 || nz < 0) throw InputError(who + "negative grid size");
    if (brick_.size() != brick_count())
        throw InputError(who + "field has " + std::to_string(brick_.size()) + " brick entries for " +
                         std::to_string(brick_count()) + " bricks");
    const std::size_t values = precision == Precision::Double ? f64_.size() : f32_.size();
    if (values % kBrickCells != 0)
        throw InputError(who + "field stores " + std::to_string(values) + " values, not whole bricks of " +
                         std::to_string(kBrickCells));
    const std::size_t stored = stored_bricks();
    for (std::size_t b = 0; b < brick_.size(); ++b)
        if (brick_[b] >= stored)
            throw InputError(who + "field brick " + std::to_string(b) + " points at stored brick " +
                             std::to_string(brick_[b]) + " of " + std::to_string(stored));
}

}  // namespace snvr
