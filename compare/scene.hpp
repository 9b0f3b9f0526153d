#pragma once
// A scene: everything one run needs, as plain structs (docs/model.md §4, §5). Filled from TOML by apps/.
#include <string>
#include <vector>

#include "continuum/params.hpp"
#include "discrete/params.hpp"

namespace slipfront::compare {

struct Scene {
  std::string name;         ///< scene name (default output directory out/<name>)
  std::string description;
  std::vector<std::string> models{"continuum"};  ///< which models to run
  continuum::InterfaceParams interface;
  continuum::BulkParams bulk;
  continuum::DriveParams drive;
  continuum::GridParams grid;
  continuum::TimeParams time;
  continuum::MeasureParams measure;
  continuum::OutputParams output;
  discrete::DiscreteParams discrete;
  /// Validate everything (throws continuum::ParamError naming the key).
  void validate() const;
};

}  // namespace slipfront::compare
