# Warnings and sanitizers as interface targets: link what you want, no global flags.
add_library(slipfront_warnings INTERFACE)
add_library(slipfront::warnings ALIAS slipfront_warnings)
target_compile_options(slipfront_warnings INTERFACE
  $<$<CXX_COMPILER_ID:GNU,Clang>:-Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion>)

add_library(slipfront_sanitizers INTERFACE)
add_library(slipfront::sanitizers ALIAS slipfront_sanitizers)
if(SLIPFRONT_SANITIZE)
  target_compile_options(slipfront_sanitizers INTERFACE -fsanitize=address,undefined -fno-omit-frame-pointer)
  target_link_options(slipfront_sanitizers INTERFACE -fsanitize=address,undefined)
endif()
