#include "snvr/devices.hpp"
#include "snvr/reconstruct.hpp"
#include "snvr/shapes.hpp"

namespace snvr {

void warmup(const std::string& device, bool single) {
    // 32 cells, one step: every kernel of the time step, the coarse solve and the
    // initialisation is launched, in well under a second once the program is built.
    Parameters p;
    p.resolution = 32;
    p.steps = 1;
    p.device = device;
    p.precision = single ? Precision::Single : Precision::Double;
    reconstruct(shapes::sphere({0.5, 0.5, 0.5}, 0.3, 0.02), p);
}

}  // namespace snvr
