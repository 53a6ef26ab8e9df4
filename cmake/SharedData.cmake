# The shared data folder (real images, calibrations) the tests and benches read: a clone away
# from the usual layout points SB_SHARED_DATA_DIR at its copy. Script-mode safe (cmake -P), so
# tests/foundation/shared_data_dir_test.cmake can check the warning.

# Sets out_var to the configure warning for dir, or to "" when dir is a folder.
function(sb_shared_data_warning dir out_var)
  if(IS_DIRECTORY "${dir}")
    set(${out_var} "" PARENT_SCOPE)
    return()
  endif()
  string(CONCAT text
    "The shared data folder ${dir} does not exist: the tests that read real data (images, "
    "calibrations) will fail (they do not skip: CI has the data). Point the CMake option "
    "SB_SHARED_DATA_DIR at your copy: cmake -DSB_SHARED_DATA_DIR=/path/to/shared/data ...")
  set(${out_var} "${text}" PARENT_SCOPE)
endfunction()
