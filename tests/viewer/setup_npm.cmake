# ctest fixture: the viewer tests' npm packages (Foxglove's ws-protocol client, CDR and IDL
# readers, schemas, MCAP reader; ws for the DevTools protocol) and their scripts in WORK_DIR.
# Exits with 77 (SKIP) when node or npm are not installed.
find_program(NODE node)
find_program(NPM npm)
if(NOT NODE OR NOT NPM)
  message("SKIP: node/npm not found; the viewer's independent clients need Node.js and npm")
  cmake_language(EXIT 77)
endif()
file(MAKE_DIRECTORY ${WORK_DIR})
foreach(f package.json package-lock.json foxglove_client.mjs browser_check.mjs derived_dump.mjs)
  configure_file(${SRC_DIR}/${f} ${WORK_DIR}/${f} COPYONLY)
endforeach()
configure_file(${VALIDATOR} ${WORK_DIR}/validate.mjs COPYONLY)
if(NOT EXISTS ${WORK_DIR}/node_modules/@foxglove/ws-protocol/package.json)
  execute_process(COMMAND ${NPM} ci --offline --no-audit --no-fund WORKING_DIRECTORY ${WORK_DIR}
                  RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
  if(NOT rc EQUAL 0)
    execute_process(COMMAND ${NPM} ci --no-audit --no-fund WORKING_DIRECTORY ${WORK_DIR}
                    RESULT_VARIABLE rc)
  endif()
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "npm ci failed in ${WORK_DIR} (no network and no npm cache?)")
  endif()
endif()
