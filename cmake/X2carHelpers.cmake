# x2car_precompile(TARGET HEADER...): the heavy third-party headers most files of TARGET include,
# parsed once per target instead of once per file (X2CAR_PRECOMPILED_HEADERS, on by default:
# about a third of a cold build's compile time is Eigen, GoogleTest and CLI11 parsed again and
# again).
function(x2car_precompile target)
  if(X2CAR_PRECOMPILED_HEADERS)
    target_precompile_headers(${target} PRIVATE ${ARGN})
  endif()
endfunction()

# x2car_reuse_precompiled(TARGET DONOR): TARGET uses DONOR's precompiled header instead of building
# its own (the same headers, the same flags): one per library and one per test binary was a
# minute of a cold build's compile time on two cores.
function(x2car_reuse_precompiled target donor)
  if(X2CAR_PRECOMPILED_HEADERS)
    target_precompile_headers(${target} REUSE_FROM ${donor})
  endif()
endfunction()

set(X2CAR_COMMON_HEADERS <Eigen/Core> <Eigen/Geometry> <algorithm> <cmath> <map> <optional>
                         <string> <vector> <fmt/format.h>)

# x2car_module(NAME SOURCES ... DEPENDS ...): one static library per module folder.
function(x2car_module name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPENDS" ${ARGN})
  add_library(x2car_${name} STATIC ${ARG_SOURCES})
  add_library(x2car::${name} ALIAS x2car_${name})
  target_include_directories(x2car_${name} PUBLIC ${PROJECT_SOURCE_DIR})
  target_link_libraries(x2car_${name} PUBLIC ${ARG_DEPENDS} PRIVATE x2car_warnings)
  # The first module (core) builds the libraries' precompiled header; the others reuse it.
  if(TARGET x2car_core AND NOT name STREQUAL "core")
    x2car_reuse_precompiled(x2car_${name} x2car_core)
  else()
    x2car_precompile(x2car_${name} ${X2CAR_COMMON_HEADERS})
  endif()
endfunction()

# x2car_tests(NAME SOURCES ... DEPENDS ...): one GoogleTest binary per module, registered with ctest.
function(x2car_tests name)
  if(NOT X2CAR_BUILD_TESTS)
    return()
  endif()
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPENDS" ${ARGN})
  # GoogleTest's main with a temp folder of each test's own (x2car/core/test_main.cpp).
  if(NOT TARGET x2car_test_main)
    add_library(x2car_test_main STATIC ${PROJECT_SOURCE_DIR}/x2car/core/test_main.cpp)
    target_link_libraries(x2car_test_main PUBLIC GTest::gtest GTest::gmock PRIVATE x2car_warnings)
  endif()
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPENDS} GTest::gtest GTest::gmock x2car_test_main
                                        x2car_warnings)
  # The first test binary builds the tests' precompiled header; the others reuse it.
  get_property(donor GLOBAL PROPERTY X2CAR_TESTS_PCH_DONOR)
  if(donor)
    x2car_reuse_precompiled(${name} ${donor})
  else()
    x2car_precompile(${name} ${X2CAR_COMMON_HEADERS} <gtest/gtest.h> <gmock/gmock.h>)
    set_property(GLOBAL PROPERTY X2CAR_TESTS_PCH_DONOR ${name})
  endif()
  # Speed is measured in bench/, never asserted here: a unit test's result must not depend on how
  # busy the machine is.
  # Each build folder has its own temp folder (::testing::TempDir(); each test a folder of its own
  # inside it, test_main.cpp), so that two checkouts testing on one machine, or two tests running
  # at once, never share the files their tests write.
  file(MAKE_DIRECTORY ${CMAKE_BINARY_DIR}/test_tmp)
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60
    PROPERTIES ENVIRONMENT "TEST_TMPDIR=${CMAKE_BINARY_DIR}/test_tmp/")
endfunction()
