# Helpers shared by every module's CMakeLists.txt.

# Warnings for our own targets (never for third-party headers, which come in as SYSTEM); errors
# with CALIBENCH_WERROR (CI).
function(calibench_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wswitch-enum
                                           -Wno-unused-parameter)
  if(CALIBENCH_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# calibench_add_library(<module> SOURCES ... PUBLIC_DEPS ... PRIVATE_DEPS ...)
# Adds target calibench_<module> with alias calibench::<module>; headers are included as
# "<module>/<file>.h" from the project root.
function(calibench_add_library module)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  set(target calibench_${module})
  add_library(${target} STATIC ${ARG_SOURCES})
  add_library(calibench::${module} ALIAS ${target})
  target_include_directories(${target} PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>)
  target_link_libraries(${target} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  calibench_set_warnings(${target})
endfunction()

# calibench_add_test(<module> <name> SOURCES ... DEPS ... [LABELS ...])
# Adds the GoogleTest executable calibench_<module>_<name>_test and registers its tests with CTest.
function(calibench_add_test module name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS;LABELS" ${ARGN})
  set(target calibench_${module}_${name}_test)
  add_executable(${target} ${ARG_SOURCES})
  target_link_libraries(${target} PRIVATE ${ARG_DEPS} GTest::gtest GTest::gtest_main)
  target_compile_definitions(${target} PRIVATE
      CALIBENCH_SOURCE_DIR="${PROJECT_SOURCE_DIR}" CALIBENCH_DATA_DIR="${CALIBENCH_DATA_DIR}"
      CALIBENCH_BUNDLED_DATA_DIR="${CALIBENCH_BUNDLED_DATA_DIR}")
  calibench_set_warnings(${target})
  gtest_discover_tests(${target} DISCOVERY_TIMEOUT 60)
  # The labels go on the discovered tests (list ${target}_TESTS) from a second include file:
  # gtest_discover_tests(PROPERTIES LABELS "a;b") expands the list on the way and keeps only "a"
  # (which is why the "data" label had no tests before).
  # The same file gives the long tests of CALIBENCH_TEST_COSTS (tests/CMakeLists.txt) their COST.
  set(labels_file "${CMAKE_CURRENT_BINARY_DIR}/${target}_labels.cmake")
  string(CONCAT content "if(${target}_TESTS)\n  set_tests_properties(\${${target}_TESTS} "
                        "PROPERTIES LABELS \"${module};${ARG_LABELS}\")\n")
  foreach(entry IN LISTS CALIBENCH_TEST_COSTS)
    string(REPLACE "=" ";" name_and_cost "${entry}")
    list(GET name_and_cost 0 test_name)
    list(GET name_and_cost 1 cost)
    string(APPEND content "  list(FIND ${target}_TESTS \"${test_name}\" index)\n"
                          "  if(NOT index EQUAL -1)\n"
                          "    set_tests_properties(\"${test_name}\" PROPERTIES COST ${cost})\n"
                          "  endif()\n")
  endforeach()
  string(APPEND content "endif()\n")
  file(WRITE "${labels_file}" "${content}")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES "${labels_file}")
endfunction()
