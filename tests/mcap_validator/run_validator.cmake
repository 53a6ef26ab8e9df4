# ctest driver: npm ci (offline cache first), write the fixture with our writer, validate it.
# Exits with 77 (ctest SKIP) when node or npm are not installed.
find_program(NODE node)
find_program(NPM npm)
if(NOT NODE OR NOT NPM)
  message("SKIP: node/npm not found; the independent MCAP validation needs Node.js and npm")
  cmake_language(EXIT 77)
endif()
file(MAKE_DIRECTORY ${WORK_DIR})
foreach(f package.json package-lock.json validate.mjs)
  configure_file(${SRC_DIR}/${f} ${WORK_DIR}/${f} COPYONLY)
endforeach()
include(${CMAKE_CURRENT_LIST_DIR}/../../cmake/NpmCi.cmake)
sb_npm_ci(${WORK_DIR} @mcap/core)
execute_process(COMMAND ${FIXTURE} ${WORK_DIR}/fixture.mcap ${WORK_DIR}/fixture_expected.json
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "fixture writer failed")
endif()
execute_process(COMMAND ${NODE} ${WORK_DIR}/validate.mjs ${WORK_DIR}/fixture.mcap
                        ${WORK_DIR}/fixture_expected.json RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "MCAP validation failed")
endif()
