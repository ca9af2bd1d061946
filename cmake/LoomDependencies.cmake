# Every third-party dependency, found once. Debian 12 packages; see README "Dependencies".

find_package(Threads REQUIRED)
find_package(Protobuf REQUIRED)
find_package(gRPC CONFIG REQUIRED)       # the job service (proto/, rpc/, server/, worker/, client/)
find_package(OpenSSL REQUIRED)          # SHA-256 for cache keys and artifact checksums
find_package(SQLite3 REQUIRED)          # the server's job queue and cache index (WAL)
find_package(spdlog REQUIRED)
find_package(nlohmann_json REQUIRED)     # canonical (sorted-key) JSON for cache keys
find_package(CLI11 REQUIRED)
find_package(PkgConfig REQUIRED)
pkg_check_modules(HTTPLIB REQUIRED IMPORTED_TARGET cpp-httplib)  # the dashboard (server/http_gateway.h)
pkg_check_modules(LIBPQ REQUIRED IMPORTED_TARGET libpq)  # PostgreSQL's client (server/store/pg_db.h)
find_package(prometheus-cpp CONFIG REQUIRED)  # metrics for Prometheus (server/server_metrics.h)
find_package(Eigen3 REQUIRED NO_MODULE)
find_package(embree 3 REQUIRED)         # ray casting for acquisition
find_package(TinyGLTF REQUIRED)         # glTF 2.0 mesh sequences of animations
find_package(Ceres REQUIRED)            # Levenberg–Marquardt lobe fitting (pulls glog, gflags)

set(OpenGL_GL_PREFERENCE GLVND)
find_package(OpenGL REQUIRED COMPONENTS OpenGL EGL)

find_package(OpenImageIO REQUIRED)
# Debian 12's OpenImageIO config lists /usr/include/opencv4 as an include directory
# although OpenCV is an optional dependency; drop it rather than install OpenCV.
get_target_property(_oiio_includes OpenImageIO::OpenImageIO INTERFACE_INCLUDE_DIRECTORIES)
if(_oiio_includes)
  list(FILTER _oiio_includes EXCLUDE REGEX "opencv")
  set_target_properties(OpenImageIO::OpenImageIO PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${_oiio_includes}")
endif()

if(LOOM_BUILD_TESTS)
  find_package(GTest REQUIRED)
  find_package(benchmark REQUIRED)      # Google Benchmark, for the timing executables
endif()
