/// \file
/// perch: where a tree-perching drone should grasp a tree (the PLI method).
/// The one include a user needs: every stage, in data-flow order.
#pragma once

#include "perch/core.hpp"
