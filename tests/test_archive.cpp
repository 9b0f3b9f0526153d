// core::Archive against stored sizes it cannot trust (issue 18): every count of a string, vector or map
// is checked against the bytes left before anything of its size is allocated, and refused with
// ArchiveError("checkpoint: <kind> size N exceeds the M bytes left ..."); what was written reads back.
#include <catch2/catch.hpp>

#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/archive.hpp"

using slipfront::core::Archive;
using slipfront::core::ArchiveError;

namespace {

struct Point {  // a class with serialize(), like the runs' records
  double t = 0.0;
  std::vector<double> v;
  template <class Ar>
  void serialize(Ar& ar) {
    ar(t, v);
  }
};

struct Nothing {  // a class that archives no bytes: its count could not be bounded
  template <class Ar>
  void serialize(Ar&) {}
};

// The bytes of a stored count followed by `tail`.
std::string count_then(std::uint64_t n, const std::string& tail) {
  Archive w = Archive::writer();
  w(n);
  return w.data() + tail;
}

template <class T>
std::function<void(Archive&)> read_into() {
  return [](Archive& ar) {
    T x;
    ar(x);
  };
}

}  // namespace

TEST_CASE("archive: a stored size beyond the bytes left is refused before allocation", "[archive][hostile]") {
  constexpr std::uint64_t huge = std::uint64_t{1} << 61, max = std::numeric_limits<std::uint64_t>::max();
  struct Case {
    const char* what;
    std::function<void(Archive&)> read;
    std::uint64_t n;
    std::string tail;
    const char* message;
  };
  const std::vector<Case> cases = {
      {"string", read_into<std::string>(), huge, "abc", "string size 2305843009213693952 exceeds the 3 bytes left"},
      {"string, the largest count", read_into<std::string>(), max, "", "string size 18446744073709551615 exceeds the 0 bytes left"},
      {"string, one byte short", read_into<std::string>(), 4, "abc", "string size 4 exceeds the 3 bytes left"},
      {"vector<double>", read_into<std::vector<double>>(), huge, std::string(16, 'x'),
       "vector size 2305843009213693952 exceeds the 16 bytes left (at least 8 bytes each)"},
      {"vector<double>, one element short", read_into<std::vector<double>>(), 3, std::string(16, 'x'),
       "vector size 3 exceeds the 16 bytes left (at least 8 bytes each)"},
      {"vector<vector<double>>", read_into<std::vector<std::vector<double>>>(), huge, std::string(40, 'x'),
       "vector size 2305843009213693952 exceeds the 40 bytes left (at least 8 bytes each)"},
      {"vector of a class", read_into<std::vector<Point>>(), huge, std::string(5, 'x'),
       "vector size 2305843009213693952 exceeds the 5 bytes left"},
      {"vector<optional<string>>", read_into<std::vector<std::optional<std::string>>>(), 1000, std::string(999, '\0'),
       "vector size 1000 exceeds the 999 bytes left"},
      {"vector<optional<double>> (a plain struct: its bytes)", read_into<std::vector<std::optional<double>>>(), 100,
       std::string(999, '\0'), "vector size 100 exceeds the 999 bytes left (at least 16 bytes each)"},
      {"map<string, double>", read_into<std::map<std::string, double>>(), huge, std::string(32, 'x'),
       "map size 2305843009213693952 exceeds the 32 bytes left (at least 16 bytes each)"},
      {"map<string, vector<double>>", read_into<std::map<std::string, std::vector<double>>>(), max, "",
       "map size 18446744073709551615 exceeds the 0 bytes left (at least 16 bytes each)"},
  };
  for (const auto& c : cases) {
    INFO(c.what);
    Archive ar = Archive::reader(count_then(c.n, c.tail));
    try {
      c.read(ar);
      FAIL_CHECK("accepted");
    } catch (const ArchiveError& e) {
      CHECK(std::string(e.what()) == std::string("checkpoint: ") + c.message);
    }
  }
  // a count inside a nested element is bounded by what is left there, not by the whole archive
  Archive w = Archive::writer();
  std::vector<Point> points(2);
  points[1].v = {1.0, 2.0};
  w(points);
  std::string bytes = w.data();
  const std::size_t second_count = bytes.size() - 2 * sizeof(double) - sizeof(std::uint64_t);
  std::uint64_t three = 3;
  bytes.replace(second_count, sizeof three, reinterpret_cast<const char*>(&three), sizeof three);
  Archive r = Archive::reader(bytes);
  std::vector<Point> back;
  CHECK_THROWS_WITH(r(back), "checkpoint: vector size 3 exceeds the 16 bytes left (at least 8 bytes each)");
}

TEST_CASE("archive: what is written reads back, sizes exactly at the bytes left included", "[archive]") {
  Archive w = Archive::writer();
  std::string s = "state";
  std::vector<double> v = {1.5, -2.0, 0.0};
  std::vector<Point> p = {{1.0, {}}, {2.0, {3.0}}};
  std::map<std::string, std::vector<double>> columns = {{"t", {0.0, 1.0}}, {"x", {}}};
  std::optional<double> o = 4.0;
  std::string empty;
  w(s, v, p, columns, o, empty);
  Archive r = Archive::reader(w.data());
  std::string s2, empty2 = "x";
  std::vector<double> v2;
  std::vector<Point> p2;
  std::map<std::string, std::vector<double>> columns2;
  std::optional<double> o2;
  r(s2, v2, p2, columns2, o2, empty2);
  CHECK(r.at_end());
  CHECK(s2 == s);
  CHECK(v2 == v);
  REQUIRE(p2.size() == 2);
  CHECK(p2[1].t == 2.0);
  CHECK(p2[1].v == std::vector<double>{3.0});
  CHECK(columns2 == columns);
  CHECK(o2 == o);
  CHECK(empty2.empty());
}

TEST_CASE("archive: an element that archives no bytes is refused when written", "[archive]") {
  Archive w = Archive::writer();
  std::vector<Nothing> v(3);
  CHECK_THROWS_AS(w(v), std::logic_error);
}
