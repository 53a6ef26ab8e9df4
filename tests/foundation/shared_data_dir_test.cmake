# cmake -DSB_SOURCE_ROOT=... -P shared_data_dir_test.cmake: a missing shared data folder gives a
# warning naming the folder and the option that points elsewhere; an existing one gives none.
include(${SB_SOURCE_ROOT}/cmake/SharedData.cmake)

# Given a folder that does not exist, when the warning is made, then it names both
set(missing "${CMAKE_CURRENT_BINARY_DIR}/sb-no-such-shared-data")
sb_shared_data_warning(${missing} text)
foreach(expected "${missing}" "SB_SHARED_DATA_DIR")
  string(FIND "${text}" "${expected}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "warning for a missing folder does not name ${expected}: '${text}'")
  endif()
endforeach()

# Given an existing folder, then there is no warning
sb_shared_data_warning(${SB_SOURCE_ROOT} text)
if(NOT text STREQUAL "")
  message(FATAL_ERROR "warning for an existing folder: '${text}'")
endif()
message(STATUS "shared data warning: ok")
