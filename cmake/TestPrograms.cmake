# Tests that run built programs (sb::testing::bin("NAME"), SB_BIN_DIR + "/NAME") must depend on
# them, so that `cmake --build build --target TEST` builds what TEST runs. sb_add_gtest records
# each test's sources; sb_check_test_programs() (end of the top CMakeLists.txt) reads them and
# lists every program a test's own files name that is not among its dependencies
# (add_dependencies(TEST ...), one level into custom targets such as demo_programs). Programs
# started by helper libraries (tests/viewer's start_viewer) are not seen: declare them by hand.

# The programs the test files name: bin("X"), SB_BIN_DIR) + "/X", and make_key_file (which runs
# stereoball-keys).
function(sb_programs_named_in files out_var)
  set(programs)
  foreach(file IN LISTS files)
    file(READ ${file} text)
    string(REGEX MATCHALL "bin\\(\"[A-Za-z0-9_.-]+\"\\)" calls "${text}")
    string(REGEX MATCHALL "SB_BIN_DIR\\) \\+ \"/[A-Za-z0-9_.-]+" paths "${text}")
    foreach(match IN LISTS calls paths)
      string(REGEX REPLACE ".*[\"/]([A-Za-z0-9_.-]+)\"?\\)?$" "\\1" program "${match}")
      list(APPEND programs ${program})
    endforeach()
    string(FIND "${text}" "make_key_file(" key_at)
    if(NOT key_at EQUAL -1)
      list(APPEND programs stereoball-keys)
    endif()
  endforeach()
  list(REMOVE_DUPLICATES programs)
  set(${out_var} ${programs} PARENT_SCOPE)
endfunction()

# Writes the missing "TEST: PROGRAM" lines to ${CMAKE_BINARY_DIR}/test_programs_missing.txt
# (read by tests/foundation/test_programs_test.cmake) and warns when there is any.
function(sb_check_test_programs)
  get_property(tests GLOBAL PROPERTY SB_GTESTS)
  set(missing)
  foreach(test IN LISTS tests)
    get_property(files GLOBAL PROPERTY SB_GTEST_SOURCES_${test})
    sb_programs_named_in("${files}" programs)
    get_target_property(deps ${test} MANUALLY_ADDED_DEPENDENCIES)
    if(NOT deps)
      set(deps)
    endif()
    set(all_deps)
    foreach(dep IN LISTS deps)
      list(APPEND all_deps ${dep})
      if(NOT TARGET ${dep})
        continue()
      endif()
      get_target_property(type ${dep} TYPE)
      if(type STREQUAL "UTILITY")
        get_target_property(inner ${dep} MANUALLY_ADDED_DEPENDENCIES)
        if(inner)
          list(APPEND all_deps ${inner})
        endif()
      endif()
    endforeach()
    foreach(program IN LISTS programs)
      if(TARGET ${program} AND NOT program IN_LIST all_deps)
        list(APPEND missing "${test}: ${program}")
      endif()
    endforeach()
  endforeach()
  list(JOIN missing "\n" text)
  file(WRITE ${CMAKE_BINARY_DIR}/test_programs_missing.txt "${text}")
  if(missing)
    message(WARNING "tests that run programs they do not depend on (add_dependencies(TEST "
                    "PROGRAM)):\n${text}")
  endif()
endfunction()
