// The depth guard a run's plan asks for (plan_guard.hpp).
#include "solver/plan_guard.hpp"

#include <limits>

namespace snvr::detail {

KeepDeep keep_deep_of(const DomainPlan& plan) {
    KeepDeep deep;
    deep.depth = plan.offset - plan.tube_inner;
    deep.voxel = plan.domain.h;
    deep.lone = plan.offset >= plan.gap ? std::numeric_limits<double>::infinity() : plan.offset;
    return deep;
}

}  // namespace snvr::detail
