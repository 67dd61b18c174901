// SPDX-License-Identifier: MIT
// The list in which post-collapse modules report the vertices they changed (moved, or
// whose edges they flipped), so a decimater can re-evaluate their neighbourhood.
#pragma once

#include "DTHexGeometry.hh"

#include <OpenMesh/Core/Utils/Property.hh>

#include <vector>

namespace dthex {

//! The mesh property "m:dthex_touched" (a std::vector of vertex handles), added if missing.
//! Modules append to it in postprocess_collapse; RevalidatingDecimaterT reads and clears it
//! after every collapse. With the stock DecimaterT nobody clears it: modules clear it
//! themselves in preprocess_collapse (before any postprocess runs).
template <class Mesh>
OpenMesh::MPropHandleT<std::vector<typename Mesh::VertexHandle>> touched_property(Mesh& mesh) {
  OpenMesh::MPropHandleT<std::vector<typename Mesh::VertexHandle>> prop;
  if (!mesh.get_property_handle(prop, touched_property_name())) mesh.add_property(prop, touched_property_name());
  return prop;
}

}  // namespace dthex
