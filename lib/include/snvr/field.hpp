// A scalar field on a Domain's grid (one sample per cell), stored in bricks of 8^3
// cells that may share storage: a reconstruction's phase field keeps only the bricks
// of its band, every other brick pointing at one shared uniform brick (+1 inside the
// shell, -1 outside), so its memory follows the surface, not the box. Build one from
// dense values with Field::from_dense (uniform bricks are shared there too); read it
// with at() or operator[], or export it whole with to_dense().
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace snvr {

enum class Precision { Double, Single };

struct Field {
    static constexpr int kBrick = 8;
    static constexpr int kBrickCells = kBrick * kBrick * kBrick;

    int nx = 0, ny = 0, nz = 0;
    Precision precision = Precision::Double;

    // Dense x-fastest values (nx * ny * nz of them) in bricks; throws ParameterError
    // when the count does not fit the shape.
    static Field from_dense(int nx, int ny, int nz, const std::vector<double>& values,
                            Precision precision = Precision::Double);
    static Field from_dense(int nx, int ny, int nz, const std::vector<float>& values);
    // The storage itself: per brick, x fastest over ceil(n / 8) bricks per axis, which
    // stored brick holds its cells (`table`); stored bricks of kBrickCells values each, x
    // fastest within a brick, cells of a partial brick beyond the grid holding anything.
    // Throws InputError when they do not fit the shape (validate).
    static Field from_bricks(int nx, int ny, int nz, std::vector<std::uint32_t> table, std::vector<double> stored);
    static Field from_bricks(int nx, int ny, int nz, std::vector<std::uint32_t> table, std::vector<float> stored);
    const std::vector<std::uint32_t>& brick_table() const { return brick_; }
    const std::vector<double>& stored_f64() const { return f64_; }  // Double's bricks (else empty)
    const std::vector<float>& stored_f32() const { return f32_; }   // Single's bricks (else empty)

    int bricks_x() const { return (nx + kBrick - 1) / kBrick; }
    int bricks_y() const { return (ny + kBrick - 1) / kBrick; }
    int bricks_z() const { return (nz + kBrick - 1) / kBrick; }
    std::size_t brick_count() const { return std::size_t(bricks_x()) * std::size_t(bricks_y()) * std::size_t(bricks_z()); }
    std::size_t stored_bricks() const { return (precision == Precision::Double ? f64_.size() : f32_.size()) / kBrickCells; }
    std::size_t size() const { return std::size_t(nx) * std::size_t(ny) * std::size_t(nz); }  // cells
    std::size_t bytes() const {
        return brick_.size() * sizeof(std::uint32_t) + f64_.size() * sizeof(double) + f32_.size() * sizeof(float);
    }

    // Where cell (i, j, k) is stored.
    std::size_t position(int i, int j, int k) const {
        const std::size_t b = std::size_t(i / kBrick) +
                              std::size_t(bricks_x()) * (std::size_t(j / kBrick) + std::size_t(bricks_y()) * std::size_t(k / kBrick));
        return std::size_t(brick_[b]) * kBrickCells + std::size_t(i % kBrick + kBrick * (j % kBrick + kBrick * (k % kBrick)));
    }
    double at(int i, int j, int k) const {
        const std::size_t p = position(i, j, k);
        return precision == Precision::Double ? f64_[p] : double(f32_[p]);
    }
    // Cell n of the x-fastest order.
    double operator[](std::size_t n) const {
        const std::size_t row = n / std::size_t(nx);
        return at(int(n % std::size_t(nx)), int(row % std::size_t(ny)), int(row / std::size_t(ny)));
    }

    // Every cell, x fastest (nx * ny * nz values).
    std::vector<double> to_dense() const;

    // Throws InputError, starting with `who`, when the brick table or the storage do
    // not fit the shape (readers call this before touching the cells).
    void validate(const std::string& who) const;

private:
    template <class Real>
    static Field make(int nx, int ny, int nz, const std::vector<Real>& values, Precision precision);
    static Field shaped(int nx, int ny, int nz, Precision precision, std::vector<std::uint32_t> table);
    std::vector<std::uint32_t> brick_;
    std::vector<double> f64_;  // used when precision == Double
    std::vector<float> f32_;   // used when precision == Single
};

}  // namespace snvr
