// SPDX-License-Identifier: MIT
// (implementation pending: foundation work)
#include "core/triangle_bvh.h"
