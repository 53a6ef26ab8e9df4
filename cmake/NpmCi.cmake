# For ctest drivers run with `cmake -P`: installs the npm packages of WORK_DIR (package.json +
# package-lock.json already copied there) unless MARKER_PACKAGE is already installed. Tries
# the npm cache first (offline), then the registry; stops with a clear error when both fail.
function(sb_npm_ci work_dir marker_package)
  find_program(NPM npm REQUIRED)
  if(EXISTS ${work_dir}/node_modules/${marker_package}/package.json)
    return()
  endif()
  execute_process(COMMAND ${NPM} ci --offline --no-audit --no-fund WORKING_DIRECTORY ${work_dir}
                  RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
  if(NOT rc EQUAL 0)
    execute_process(COMMAND ${NPM} ci --no-audit --no-fund WORKING_DIRECTORY ${work_dir}
                    RESULT_VARIABLE rc)
  endif()
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "npm ci failed in ${work_dir} (no network and no npm cache?)")
  endif()
endfunction()
