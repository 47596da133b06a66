# risas_add_gtest(<name> <sources>... [COST <cost>])
# One way to declare a GoogleTest executable for both builds: catkin's
# run_tests (XML results for catkin_test_results) inside a workspace, ctest
# with plain CMake. COST: ctest -j starts tests of higher cost first (a
# fresh build has no timings of its own); give it to an executable with a
# test that runs for minutes under a sanitizer, so that it does not start
# last and run alone. Tests get RISAS_BIN_DIR to find the command-line tools
# and RISAS_SOURCE_DIR to find the shipped files.
if(RISAS_USE_CATKIN)
  find_package(GTest QUIET)
else()
  find_package(GTest REQUIRED)
  include(GoogleTest)
endif()

function(risas_add_gtest name)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "COST" "")
  if(RISAS_USE_CATKIN)
    catkin_add_gtest(${name} ${arg_UNPARSED_ARGUMENTS} WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
    if(NOT TARGET ${name})
      return()
    endif()
    target_link_libraries(${name} risas_core risas_synthetic gtest_main)
  else()
    add_executable(${name} ${arg_UNPARSED_ARGUMENTS})
    target_link_libraries(${name} risas_core risas_synthetic GTest::gtest_main)
    set(properties)
    if(arg_COST)
      set(properties PROPERTIES COST ${arg_COST})
    endif()
    gtest_discover_tests(${name} WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR}
      DISCOVERY_TIMEOUT 60 ${properties})
  endif()
  target_compile_definitions(${name} PRIVATE RISAS_BIN_DIR="${RISAS_BIN_DIR}" RISAS_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR}/test)
endfunction()
