// SPDX-License-Identifier: MIT
// The bundled meshes (meshes/ in the source tree), by file name, for the tests that read them.
#pragma once

#include <dthex/io/read_surface.h>
#include <dthex/mesh/types.h>

#include <string>

namespace dthex_test {

//! The path of meshes/NAME in the source tree.
inline std::string bundled_mesh(const std::string& name) { return std::string(DTHEX_SOURCE_DIR) + "/meshes/" + name; }

//! meshes/NAME read as the pipeline reads it.
inline dthex::TriSurface read_bundled_mesh(const std::string& name) { return dthex::read_surface(bundled_mesh(name)); }

}  // namespace dthex_test
