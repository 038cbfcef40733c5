// Umbrella header: the library's public API (by job: shell.hpp the one call and its
// settings, point_io.hpp points and their reading, mesh_io.hpp meshes and their
// writing, devices.hpp, quality.hpp). The sampler's test shapes (shapes.hpp), the
// stopwatch (stopwatch.hpp) and PNG pictures (render.hpp) are included on their own.
#pragma once
#include "snvr/devices.hpp"
#include "snvr/domain.hpp"
#include "snvr/error.hpp"
#include "snvr/field.hpp"
#include "snvr/formats.hpp"
#include "snvr/geometry.hpp"
#include "snvr/mesh.hpp"
#include "snvr/mesh_io.hpp"
#include "snvr/parameters.hpp"
#include "snvr/point_cloud.hpp"
#include "snvr/point_io.hpp"
#include "snvr/quality.hpp"
#include "snvr/reconstruct.hpp"
#include "snvr/report.hpp"
#include "snvr/shell.hpp"
