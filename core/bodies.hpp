#pragma once
// The bodies a scene can run, and the one map from core::BodyKind (decided by BulkParams::body()) to the
// body class (docs/architecture.md "Where a new thing goes"). A new body is its class (a core::RunBody),
// one BodyKind, the rule in BulkParams::body() that picks it, and one case here.
#include <type_traits>
#include <utility>

#include "core/bulk.hpp"
#include "core/inplane.hpp"
#include "core/params.hpp"
#include "core/strip.hpp"

namespace slipfront::core {

/// Calls f(std::type_identity<B>{}) with B the class of body `kind`.
template <class F>
decltype(auto) with_body(BodyKind kind, F&& f) {
  switch (kind) {
    case BodyKind::strip: return std::forward<F>(f)(std::type_identity<Strip>{});
    case BodyKind::inplane: return std::forward<F>(f)(std::type_identity<InPlane>{});
    case BodyKind::chain: break;
  }
  return std::forward<F>(f)(std::type_identity<Bulk>{});
}

}  // namespace slipfront::core
