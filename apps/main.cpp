// slipfront: the command-line program (verbs and options: docs/cli.md).
#include <exception>
#include <iostream>

#include "apps/cli.hpp"

int main(int argc, char** argv) {
  try {
    return slipfront::app::main_cli(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "slipfront: error: " << e.what() << "\n";
    return slipfront::app::exit_code::failed;
  }
}
