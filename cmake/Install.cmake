# Install rules and the Debian package (cpack -G DEB).
#
# Layout (GNUInstallDirs, relocatable: programs find their data relative to themselves):
#   bin/stereoball                          the one command on PATH
#   libexec/stereoball/                     the nodes and the stereoball-* subcommands
#   share/stereoball/{config,deploy,idl}    shipped parameters, profiles, messages
#   lib/systemd/system/stereoball-*.service the robot and workstation roles
# /etc/stereoball/<file> overrides a single shipped config file (search order:
# components/common/util/install_layout.hpp).
include(GNUInstallDirs)

set(SB_INSTALL_PROGRAMS_DIR ${CMAKE_INSTALL_LIBEXECDIR}/stereoball)

# Every executable target below dir, except tests and test helpers (anything under tests/
# or built into the tests output folder).
function(sb_collect_programs dir out)
  get_property(targets DIRECTORY ${dir} PROPERTY BUILDSYSTEM_TARGETS)
  get_property(subdirs DIRECTORY ${dir} PROPERTY SUBDIRECTORIES)
  set(found)
  foreach(t IN LISTS targets)
    get_target_property(type ${t} TYPE)
    get_target_property(outdir ${t} RUNTIME_OUTPUT_DIRECTORY)
    if(type STREQUAL "EXECUTABLE" AND NOT outdir STREQUAL "${CMAKE_BINARY_DIR}/tests")
      list(APPEND found ${t})
    endif()
  endforeach()
  foreach(sub IN LISTS subdirs)
    if(NOT sub MATCHES "^${CMAKE_SOURCE_DIR}/tests(/|$)")
      sb_collect_programs(${sub} sub_found)
      list(APPEND found ${sub_found})
    endif()
  endforeach()
  set(${out} ${found} PARENT_SCOPE)
endfunction()

sb_collect_programs(${CMAKE_SOURCE_DIR} SB_PROGRAMS)
list(REMOVE_ITEM SB_PROGRAMS stereoball)
install(TARGETS stereoball RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS ${SB_PROGRAMS} RUNTIME DESTINATION ${SB_INSTALL_PROGRAMS_DIR})
file(RELATIVE_PATH sb_programs_rel ${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_BINDIR}
     ${CMAKE_INSTALL_PREFIX}/${SB_INSTALL_PROGRAMS_DIR})
target_compile_definitions(stereoball PRIVATE SB_PROGRAMS_REL="${sb_programs_rel}")

install(DIRECTORY config deploy DESTINATION ${CMAKE_INSTALL_DATADIR}/stereoball
        PATTERN "systemd" EXCLUDE)
install(FILES idl/stereoball.idl DESTINATION ${CMAKE_INSTALL_DATADIR}/stereoball/idl)
install(FILES deploy/systemd/stereoball-robot.service deploy/systemd/stereoball-workstation.service
        DESTINATION lib/systemd/system)
install(FILES deploy/systemd/stereoball.env.example deploy/systemd/90-stereoball-net.conf
        README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(FILES deploy/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR} RENAME README.deploy.md)

# The Debian package: one package, two systemd roles (stereoball-robot.service,
# stereoball-workstation.service). Library dependencies come from dpkg-shlibdeps, so they
# name exactly the sonames the programs link.
set(CPACK_PACKAGE_NAME stereoball)
set(CPACK_PACKAGE_VENDOR "StereoBall")
set(CPACK_PACKAGE_CONTACT "StereoBall developers <stereoball@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "stereo vision ball detection and following for mobile robots over Cyclone DDS")
set(CPACK_PACKAGE_DESCRIPTION
    "Finds a ball in a stereo camera pair, locates it in 3D and drives a mobile robot to\n"
    "follow it. Independent processes (camera_server, ball_detector, tracker,\n"
    "motion_controller, simulator) exchange messages over Cyclone DDS.")
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# adduser: postinst creates the system user the roles run as.
set(CPACK_DEBIAN_PACKAGE_DEPENDS "adduser")
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "cyclonedds-tools")
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA ${CMAKE_SOURCE_DIR}/deploy/debian/postinst)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
include(CPack)
