# Run at every build (the target slipfront_git_commit in apps/CMakeLists.txt): writes the commit the
# sources are at (`git describe --always --dirty`, "unknown" outside a git checkout) into OUT, a one-line
# C++ source, only when it changed, so /meta git_commit and --version name the commit a binary was built
# from, not the one CMake was configured at.
#   cmake -DGIT=<git> -DSRC=<source dir> -DOUT=<file> -P git_commit.cmake
set(commit "unknown")
if(GIT)
  execute_process(COMMAND ${GIT} describe --always --dirty WORKING_DIRECTORY ${SRC}
    OUTPUT_VARIABLE described OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE rc ERROR_QUIET)
  if(rc EQUAL 0 AND NOT described STREQUAL "")
    set(commit "${described}")
  endif()
endif()
set(content "// Generated at build time by apps/git_commit.cmake.\n#include \"apps/build_info.hpp\"\n\nnamespace slipfront::app::build_info {\nconst char* const git_commit = \"${commit}\";\n}  // namespace slipfront::app::build_info\n")
set(old "")
if(EXISTS "${OUT}")
  file(READ "${OUT}" old)
endif()
if(NOT old STREQUAL content)
  file(WRITE "${OUT}" "${content}")
endif()
