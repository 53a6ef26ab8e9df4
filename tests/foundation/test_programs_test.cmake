# cmake -DLIST=.../test_programs_missing.txt -P test_programs_test.cmake: every test depends on
# the programs its files run (the list sb_check_test_programs wrote at configure time is empty).
if(NOT EXISTS "${LIST}")
  message(FATAL_ERROR "${LIST} is missing: configure again (cmake/TestPrograms.cmake)")
endif()
file(READ "${LIST}" missing)
if(NOT missing STREQUAL "")
  message(FATAL_ERROR "tests lacking add_dependencies(TEST PROGRAM) for what they run:\n"
                      "${missing}")
endif()
message(STATUS "every test depends on the programs it runs")
