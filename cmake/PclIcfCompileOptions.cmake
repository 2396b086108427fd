# The linker. GNU ld spends 10-12 s on each of our executables (PCL, VTK and OpenMPI bring some
# hundred shared libraries); LLVM's lld links the same one in under a second, gold in about one.
# PCL_ICF_LINKER: lld, gold or bfd (the compiler's default); the first of lld, gold that the
# compiler accepts when unset. Under lld the Python module is linked without pybind11's LTO
# (python/CMakeLists.txt): lld cannot read GCC's LTO objects.
include(CheckCXXSourceCompiles)
function(pcl_icf_linker_works linker result)
  set(CMAKE_REQUIRED_LINK_OPTIONS -fuse-ld=${linker})
  check_cxx_source_compiles("int main() { return 0; }" ${result})
endfunction()
if(NOT DEFINED PCL_ICF_LINKER)
  set(chosen bfd)
  foreach(candidate lld gold)
    pcl_icf_linker_works(${candidate} PCL_ICF_HAVE_LINKER_${candidate})
    if(PCL_ICF_HAVE_LINKER_${candidate})
      set(chosen ${candidate})
      break()
    endif()
  endforeach()
  set(PCL_ICF_LINKER ${chosen} CACHE STRING "Linker: lld, gold or bfd (the compiler's default)")
endif()
set_property(CACHE PCL_ICF_LINKER PROPERTY STRINGS lld gold bfd)
if(NOT PCL_ICF_LINKER MATCHES "^(lld|gold|bfd)$")
  message(FATAL_ERROR "PCL_ICF_LINKER=${PCL_ICF_LINKER}: expected lld, gold or bfd")
endif()
if(NOT PCL_ICF_LINKER STREQUAL "bfd")
  add_link_options(-fuse-ld=${PCL_ICF_LINKER})
endif()
message(STATUS "pcl_icf: linking with ${PCL_ICF_LINKER}")

# Warnings and sanitizers for our own targets only (PCL's headers are SYSTEM includes).
function(pcl_icf_target_defaults target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic)
  if(PCL_ICF_WARNINGS_AS_ERRORS)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
  if(PCL_ICF_SANITIZE)
    target_compile_options(${target} PRIVATE -fsanitize=${PCL_ICF_SANITIZE} -fno-omit-frame-pointer
                                             -fno-sanitize-recover=all)
    target_link_options(${target} PRIVATE -fsanitize=${PCL_ICF_SANITIZE})
  endif()
endfunction()

# Precompiled headers: the standard library, Eigen and PCL's point and mesh types that nearly
# every source includes (and GoogleTest for the tests) are parsed once per library or program and
# once for all the tests, instead of once per source: about 3 s of each 5-20 s compile.
# PCL_ICF_PRECOMPILE_HEADERS=OFF compiles every source alone, which checks that it includes what
# it uses.
option(PCL_ICF_PRECOMPILE_HEADERS "Precompile the standard, Eigen and PCL headers most sources use" ON)
set(PCL_ICF_COMMON_HEADERS
    <algorithm> <array> <cmath> <cstdint> <functional> <iostream> <limits> <map> <memory>
    <sstream> <string> <unordered_map> <vector> <Eigen/Core> <Eigen/Geometry> <pcl/PolygonMesh.h>
    <pcl/point_cloud.h> <pcl/point_types.h>)

# pcl_icf_precompile_headers(TARGET [header...]): TARGET's sources compiled with the given
# headers, then the common ones, precompiled (for a target of several sources).
function(pcl_icf_precompile_headers target)
  if(PCL_ICF_PRECOMPILE_HEADERS)
    target_precompile_headers(${target} PRIVATE ${ARGN} ${PCL_ICF_COMMON_HEADERS})
  endif()
endfunction()

# pcl_icf_add_library(ROOM SOURCES file... [PUBLIC dependency...] [PRIVATE dependency...])
# One room's library: target pcl_icf_ROOM, exported and aliased as pcl_icf::ROOM; the room's
# include/ folder public (installed under include/pcl_icf), internal/ (the helpers shared by the
# libraries' sources, not installed) private; the project's warnings and sanitizers.
function(pcl_icf_add_library room)
  cmake_parse_arguments(PARSE_ARGV 1 ARG "" "" "SOURCES;PUBLIC;PRIVATE")
  if(ARG_UNPARSED_ARGUMENTS OR NOT ARG_SOURCES)
    message(FATAL_ERROR "pcl_icf_add_library(${room}): SOURCES expected, "
                        "got '${ARG_UNPARSED_ARGUMENTS}'")
  endif()
  set(target pcl_icf_${room})
  add_library(${target} ${ARG_SOURCES})
  add_library(pcl_icf::${room} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${room})
  target_include_directories(${target}
    PUBLIC $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include> $<INSTALL_INTERFACE:include/pcl_icf>
    PRIVATE ${PROJECT_SOURCE_DIR}/internal)
  target_link_libraries(${target} PUBLIC ${ARG_PUBLIC} PRIVATE ${ARG_PRIVATE})
  pcl_icf_target_defaults(${target})
  # Precompiling costs about what three sources save.
  list(LENGTH ARG_SOURCES source_count)
  if(source_count GREATER 3)
    pcl_icf_precompile_headers(${target})
  endif()
  install(DIRECTORY include/ DESTINATION include/pcl_icf)
endfunction()

# PCL 1.13 has no imported targets: wrap its variables in one interface target.
add_library(pcl_icf_pcl_deps INTERFACE)
target_include_directories(pcl_icf_pcl_deps SYSTEM INTERFACE ${PCL_INCLUDE_DIRS})
target_link_libraries(pcl_icf_pcl_deps INTERFACE ${PCL_LIBRARIES} Eigen3::Eigen)
target_compile_definitions(pcl_icf_pcl_deps INTERFACE ${PCL_DEFINITIONS})

# Under ASan, Eigen switches to its own aligned allocator (__SANITIZE_ADDRESS__), while the
# precompiled PCL libraries free with plain free(): a false "free on address not malloc()-ed"
# in pcl::ConvexHull. Tell Eigen that malloc is aligned, as it is on x86-64 glibc.
if(PCL_ICF_SANITIZE)
  target_compile_definitions(pcl_icf_pcl_deps INTERFACE EIGEN_MALLOC_ALREADY_ALIGNED=1)
endif()
