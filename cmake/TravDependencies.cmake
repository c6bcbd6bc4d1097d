# Every dependency is a Debian bookworm package (scripts/install-deps); nothing is downloaded.
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(yaml-cpp REQUIRED)
find_package(nlohmann_json 3.10 REQUIRED)
find_package(fmt REQUIRED)
find_package(CLI11 REQUIRED)
find_package(mujoco 2.2.2 REQUIRED)
find_package(PNG REQUIRED)
find_package(Threads REQUIRED)
# OSMesa and EGL are loaded at run time with dlopen (renders/gl_context.cc), so only their headers are needed.
find_path(TRAV_OSMESA_INCLUDE_DIR GL/osmesa.h REQUIRED)
find_path(TRAV_EGL_INCLUDE_DIR EGL/egl.h REQUIRED)
# liblbfgs (Debian liblbfgs-dev) ships no CMake config
find_library(TRAV_LBFGS_LIBRARY lbfgs REQUIRED)
# libzstd (Debian libzstd-dev) compresses run.mcap's chunks; its CMake config is not packaged
find_library(TRAV_ZSTD_LIBRARY zstd REQUIRED)
