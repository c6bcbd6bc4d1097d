# trav_warnings: an INTERFACE target every trav target links PRIVATE.
add_library(trav_warnings INTERFACE)
target_compile_options(trav_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wimplicit-fallthrough -Wvla -Wunused)
if(TRAV_WERROR)
  target_compile_options(trav_warnings INTERFACE -Werror)
endif()
