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
foreach(f package.json package-lock.json foxglove_client.mjs browser_check.mjs derived_dump.mjs
    calibrate_check.mjs)
  configure_file(${SRC_DIR}/${f} ${WORK_DIR}/${f} COPYONLY)
endforeach()
configure_file(${VALIDATOR} ${WORK_DIR}/validate.mjs COPYONLY)
configure_file(${SRC_DIR}/../../tools/view/client/view_chromium.mjs ${WORK_DIR}/view_chromium.mjs
  COPYONLY)
include(${CMAKE_CURRENT_LIST_DIR}/../../cmake/NpmCi.cmake)
sb_npm_ci(${WORK_DIR} @foxglove/ws-protocol)
