#pragma once
// A minimal binary archive for checkpoints (issue 10: `slipfront run --checkpoint-every`, `--restart`):
// every stateful class has `template <class Ar> void serialize(Ar& ar)` naming its state once, and the
// same function writes and reads it. Values are stored as their bytes (doubles bit for bit), containers
// with their sizes. A checkpoint is read back by the same build on the same machine kind (it is not a
// portable exchange format; the results file is). Written by hand rather than pulling in
// Boost.Serialization: the archive itself is these sixty lines, the work is in the serialize functions,
// which any library would need too.
#include <array>
#include <concepts>
#include <cstdint>
#include <cstring>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace slipfront::core {

struct ArchiveError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Archive {
 public:
  static Archive writer() { return Archive(false, {}); }
  static Archive reader(std::string data) { return Archive(true, std::move(data)); }
  bool loading() const { return loading_; }
  const std::string& data() const { return data_; }
  bool at_end() const { return pos_ == data_.size(); }

  template <class T>
  Archive& operator()(T& x) {
    if constexpr (std::is_arithmetic_v<T> || std::is_enum_v<T>) {
      bytes(&x, sizeof x);
    } else if constexpr (std::is_same_v<T, std::string>) {
      std::uint64_t n = x.size();
      (*this)(n);
      if (loading_) x.assign(take(n), n);
      else data_.append(x);
    } else if constexpr (requires { x.serialize(*this); }) {
      x.serialize(*this);
    } else if constexpr (std::is_trivially_copyable_v<T> && std::is_standard_layout_v<T>) {
      bytes(&x, sizeof x);  // plain structs of numbers
    } else {
      container(x);
    }
    return *this;
  }
  template <class T, class... Rest>
  Archive& operator()(T& x, Rest&... rest) {
    (*this)(x);
    return (*this)(rest...);
  }
  /// A tag checked on reading: a mismatch means the checkpoint is not of this kind of run.
  void tag(const char* name) {
    std::string t = name;
    (*this)(t);
    if (loading_ && t != name) throw ArchiveError(std::string("checkpoint: expected '") + name + "', found '" + t + "'");
  }

 private:
  Archive(bool loading, std::string data) : loading_(loading), data_(std::move(data)) {}
  void bytes(void* p, std::size_t n) {
    if (loading_) std::memcpy(p, take(n), n);
    else data_.append(static_cast<const char*>(p), n);
  }
  const char* take(std::size_t n) {
    if (n > data_.size() - pos_) throw ArchiveError("checkpoint: truncated state");
    const char* p = data_.data() + pos_;
    pos_ += n;
    return p;
  }
  template <class T>
  void container(std::vector<T>& v) {
    std::uint64_t n = v.size();
    (*this)(n);
    if (loading_) v.resize(n);
    if constexpr (std::is_arithmetic_v<T>) {
      if (n) bytes(v.data(), n * sizeof(T));
    } else {
      for (auto& e : v) (*this)(e);
    }
  }
  template <class K, class V>
  void container(std::map<K, V>& m) {
    std::uint64_t n = m.size();
    (*this)(n);
    if (loading_) {
      m.clear();
      for (std::uint64_t k = 0; k < n; ++k) {
        std::pair<K, V> e;
        (*this)(e.first, e.second);
        m.emplace(std::move(e));
      }
    } else {
      for (auto& [k, v] : m) {
        K key = k;
        (*this)(key, v);
      }
    }
  }
  template <class T>
  void container(std::optional<T>& o) {
    bool has = o.has_value();
    (*this)(has);
    if (loading_) o = has ? std::optional<T>(T{}) : std::nullopt;
    if (has) (*this)(*o);
  }
  template <class A, class B>
  void container(std::pair<A, B>& p) {
    (*this)(p.first, p.second);
  }

  bool loading_;
  std::string data_;
  std::size_t pos_ = 0;
};

}  // namespace slipfront::core
