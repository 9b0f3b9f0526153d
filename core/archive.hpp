#pragma once
// A minimal binary archive for checkpoints (issue 10: `slipfront run --checkpoint-every`, `--restart`):
// every stateful class has `template <class Ar> void serialize(Ar& ar)` naming its state once, and the
// same function writes and reads it. Values are stored as their bytes (doubles bit for bit), containers
// with their sizes. A checkpoint is read back by the same build on the same machine kind (it is not a
// portable exchange format; the results file is). Written by hand rather than pulling in
// Boost.Serialization: the archive itself is these hundred lines, the work is in the serialize functions,
// which any library would need too.
//
// Reading trusts no stored size (issue 18): a count of n elements is refused before anything is
// allocated when n times the least number of bytes one element takes (archived_min_bytes) exceeds the
// bytes left. An element of a container therefore takes at least one byte; the writer checks it.
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

template <class T>
struct is_archived_container : std::false_type {};
template <class T, class A>
struct is_archived_container<std::vector<T, A>> : std::true_type {};
template <class K, class V, class C, class A>
struct is_archived_container<std::map<K, V, C, A>> : std::true_type {};

class Archive;

/// The least number of bytes one value of T takes in an archive, in the order Archive::operator()
/// dispatches: numbers and plain structs their size, a string or a container its 8-byte count, an
/// optional its flag, a pair both; a class with serialize() at least 1 (checked when written).
template <class T>
constexpr std::uint64_t archived_min_bytes() {
  if constexpr (std::is_arithmetic_v<T> || std::is_enum_v<T>) return sizeof(T);
  else if constexpr (std::is_same_v<T, std::string> || is_archived_container<T>::value) return sizeof(std::uint64_t);
  else if constexpr (requires(T& x, Archive& ar) { x.serialize(ar); }) return 1;
  else if constexpr (std::is_trivially_copyable_v<T> && std::is_standard_layout_v<T>) return sizeof(T);
  else if constexpr (requires { typename T::first_type; typename T::second_type; })
    return archived_min_bytes<std::remove_const_t<typename T::first_type>>() + archived_min_bytes<typename T::second_type>();
  else return sizeof(bool);  // std::optional
}

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
      if (loading_) x.assign(take(bounded(n, 1, "string")), n);
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
  /// A stored count of n elements of at least `each` bytes, checked against the bytes left before
  /// anything of its size is allocated.
  std::uint64_t bounded(std::uint64_t n, std::uint64_t each, const char* what) const {
    const std::uint64_t left = data_.size() - pos_;
    if (n > left / each)
      throw ArchiveError("checkpoint: " + std::string(what) + " size " + std::to_string(n) + " exceeds the " +
                         std::to_string(left) + " bytes left" +
                         (each > 1 ? " (at least " + std::to_string(each) + " bytes each)" : std::string()));
    return n;
  }
  /// Writes one element of a container: it must take at least a byte (what bounded() assumes).
  template <class T>
  void element(T& e) {
    const std::size_t before = data_.size();
    (*this)(e);
    if (!loading_ && data_.size() == before)
      throw std::logic_error("checkpoint: an element of a container was archived as no bytes (its count could not be checked)");
  }
  template <class T>
  void container(std::vector<T>& v) {
    std::uint64_t n = v.size();
    (*this)(n);
    if (loading_) v.resize(bounded(n, archived_min_bytes<T>(), "vector"));
    if constexpr (std::is_arithmetic_v<T>) {
      if (n) bytes(v.data(), n * sizeof(T));
    } else {
      for (auto& e : v) element(e);
    }
  }
  template <class K, class V>
  void container(std::map<K, V>& m) {
    std::uint64_t n = m.size();
    (*this)(n);
    if (loading_) {
      bounded(n, archived_min_bytes<K>() + archived_min_bytes<V>(), "map");
      m.clear();
      for (std::uint64_t k = 0; k < n; ++k) {
        std::pair<K, V> e;
        (*this)(e.first, e.second);
        m.emplace(std::move(e));
      }
    } else {
      for (auto& [k, v] : m) {
        K key = k;
        const std::size_t before = data_.size();
        (*this)(key, v);
        if (data_.size() == before) throw std::logic_error("checkpoint: an element of a map was archived as no bytes");
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
