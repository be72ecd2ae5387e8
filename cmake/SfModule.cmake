# sf_module(NAME SOURCES ... DEPS ...): one library per module under libs/<name>,
# public headers in libs/<name>/include/sf/<name>/, linked as sf::<name>.
function(sf_module name)
  cmake_parse_arguments(M "" "" "SOURCES;DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(sf_${name} ${M_SOURCES})
  add_library(sf::${name} ALIAS sf_${name})
  target_include_directories(sf_${name} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include
                                        PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src)
  target_link_libraries(sf_${name} PUBLIC ${M_DEPS} PRIVATE sf_warnings ${M_PRIVATE_DEPS})
endfunction()

# sf_unit_test(NAME SOURCES ... DEPS ... [LABELS ...]): a GoogleTest binary whose tests carry
# the label "unit" so `ctest -L unit` runs exactly them. Extra labels: "scale" marks runs of
# thousands of simulated steps that the asan preset leaves out (their code paths run under
# ASan in the smaller tests of the same module).
function(sf_unit_test name)
  cmake_parse_arguments(T "" "" "SOURCES;DEPS;LABELS" ${ARGN})
  if(NOT SF_BUILD_TESTS)
    return()
  endif()
  add_executable(${name} ${T_SOURCES})
  set_property(GLOBAL APPEND PROPERTY SF_UNIT_TESTS ${name})
  # The test code itself at -O1 in the optimised builds: it drives the libraries' -O2 code, its
  # own speed does not matter, and -O1 spends less of the build on the tests.
  if(CMAKE_BUILD_TYPE MATCHES "^(RelWithDebInfo|Release)$")
    target_compile_options(${name} PRIVATE -O1)
  endif()
  target_link_libraries(${name} PRIVATE ${T_DEPS} sf::core_testing GTest::gtest GTest::gmock GTest::gtest_main sf_warnings)
  # SF_SOURCE_DIR: tests that start peers from the repository (node-opcua, Jena) find it there.
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60
                       PROPERTIES LABELS unit ENVIRONMENT "SF_SOURCE_DIR=${PROJECT_SOURCE_DIR}")
  # Extra labels are set by a script ctest reads after the discovered tests: a list in
  # PROPERTIES reaches set_tests_properties split, its second label taken for a property.
  if(T_LABELS)
    set(script "${CMAKE_CURRENT_BINARY_DIR}/${name}_labels.cmake")
    file(WRITE "${script}"
         "foreach(t IN LISTS ${name}_TESTS)\n"
         "  set_tests_properties(\"\${t}\" PROPERTIES LABELS \"unit;${T_LABELS}\")\n"
         "endforeach()\n")
    set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES "${script}")
  endif()
endfunction()

# The `unit_tests` target builds every binary the "unit" label runs and nothing else (the asan
# build preset builds only it: the CLI, integration peers and benchmarks are not needed there).
# Called once at the end of the top-level CMakeLists.txt, when every module has registered.
function(sf_unit_tests_target)
  if(NOT SF_BUILD_TESTS)
    return()
  endif()
  get_property(tests GLOBAL PROPERTY SF_UNIT_TESTS)
  add_custom_target(unit_tests)
  add_dependencies(unit_tests ${tests})
endfunction()
