// Umbrella header: everything a user of libsnvr needs.
#pragma once
#include "snvr/domain.hpp"
#include "snvr/error.hpp"
#include "snvr/field.hpp"
#include "snvr/geometry.hpp"
#include "snvr/io.hpp"
#include "snvr/mesh.hpp"
#include "snvr/parameters.hpp"
#include "snvr/quality.hpp"
#include "snvr/reconstruct.hpp"
#include "snvr/shapes.hpp"
#include "snvr/devices.hpp"
#include "snvr/stopwatch.hpp"
