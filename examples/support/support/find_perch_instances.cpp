// SPDX-License-Identifier: BSL-1.0
// The definitions find_perch_instances.hpp declares: the pipeline, compiled once per build for
// the tests and the perch tool. One translation unit, so that the inline stages the fifteen
// instances share are compiled once too.
#include "support/find_perch_instances.hpp"

namespace perch {

#define PERCH_FIND_PERCH_DEFINE(Platform, Scale) template PERCH_FIND_PERCH_INSTANCE(Platform, Scale)
PERCH_FIND_PERCH_INSTANCES(PERCH_FIND_PERCH_DEFINE)
#undef PERCH_FIND_PERCH_DEFINE

}  // namespace perch
