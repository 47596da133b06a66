# risas_add_gtest(<name> <sources>...)
# One way to declare a GoogleTest executable for both builds: catkin's
# run_tests (XML results for catkin_test_results) inside a workspace, ctest
# with plain CMake. Tests get RISAS_BIN_DIR to find the command-line tools
# and RISAS_SOURCE_DIR to find the shipped files.
if(RISAS_USE_CATKIN)
  find_package(GTest QUIET)
else()
  find_package(GTest REQUIRED)
  include(GoogleTest)
endif()

function(risas_add_gtest name)
  if(RISAS_USE_CATKIN)
    catkin_add_gtest(${name} ${ARGN} WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
    if(NOT TARGET ${name})
      return()
    endif()
    target_link_libraries(${name} risas_core risas_synthetic gtest_main)
  else()
    add_executable(${name} ${ARGN})
    target_link_libraries(${name} risas_core risas_synthetic GTest::gtest_main)
    gtest_discover_tests(${name} WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR}
      DISCOVERY_TIMEOUT 60)
  endif()
  target_compile_definitions(${name} PRIVATE RISAS_BIN_DIR="${RISAS_BIN_DIR}" RISAS_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR}/test)
endfunction()
