// SPDX-License-Identifier: BSL-1.0
// Counts global operator new calls, so a test can assert that a hot path allocates nothing:
//   perch::test::allocation_scope scope;  ...call...;  CHECK(scope.count() == 0);
#pragma once

#include <atomic>

namespace perch::test {

extern std::atomic<long long> g_allocations;

/// Allocations made since construction.
class allocation_scope {
 public:
  allocation_scope() noexcept : start_(g_allocations.load()) {}
  [[nodiscard]] long long count() const noexcept { return g_allocations.load() - start_; }

 private:
  long long start_;
};

}  // namespace perch::test
