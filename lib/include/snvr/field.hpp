// A scalar field on a Domain's grid, stored in the precision the solver ran in.
#pragma once
#include <cstddef>
#include <vector>

namespace snvr {

enum class Precision { Double, Single };

struct Field {
    int nx = 0, ny = 0, nz = 0;
    Precision precision = Precision::Double;
    std::vector<double> f64;  // used when precision == Double
    std::vector<float> f32;   // used when precision == Single

    std::size_t size() const { return std::size_t(nx) * std::size_t(ny) * std::size_t(nz); }
    double operator[](std::size_t n) const {
        return precision == Precision::Double ? f64[n] : double(f32[n]);
    }
    double at(int i, int j, int k) const {
        return (*this)[std::size_t(i) + std::size_t(nx) * (std::size_t(j) + std::size_t(ny) * std::size_t(k))];
    }
};

}  // namespace snvr
