# Project-wide CMake helpers. Every component uses these so that tests, domain
# ids and output folders stay uniform.

set(SB_SOURCE_ROOT ${CMAKE_SOURCE_DIR})
# Real data shipped beside the project (read-only, never copied in): ../shared/data unless the
# cache option says otherwise; a missing folder is a configure warning naming the option.
get_filename_component(sb_default_shared_data ${CMAKE_SOURCE_DIR}/../shared/data ABSOLUTE)
set(SB_SHARED_DATA_DIR ${sb_default_shared_data} CACHE PATH
    "Shared data folder the tests and benches read (default ../shared/data beside the source)")
get_filename_component(SB_SHARED_DATA_DIR ${SB_SHARED_DATA_DIR} ABSOLUTE)
include(${CMAKE_CURRENT_LIST_DIR}/SharedData.cmake)
include(${CMAKE_CURRENT_LIST_DIR}/TestPrograms.cmake)
sb_shared_data_warning(${SB_SHARED_DATA_DIR} sb_shared_data_warning_text)
if(sb_shared_data_warning_text)
  message(WARNING "${sb_shared_data_warning_text}")
endif()

# Build speed: precompiled headers (off by default). The standard library, OpenCV core/imgproc
# and (in tests) GoogleTest are parsed once per build into a shared precompiled header instead of
# once per target: sb_pch for every C++ target, sb_pch_test for the targets that link GoogleTest.
# Measured with unity builds (one file per target), they do not pay: loading the 110-130 MB
# header costs about 0.9 CPU s per file, against 1 to 2.5 s of parsing saved where a file uses
# all of it, and more than it saves where a file uses little of it (tools/build_cpu_times.sh;
# DEVELOPERS.md). sb_use_precompiled_headers() (called at the end of the top CMakeLists.txt)
# gives every target one of the two, so new targets need nothing. A target or file built with its
# own -std/-m options, or a target with C files, is left out; -Winvalid-pch makes any other
# refusal a warning (an error in CI). GCC only (clang refuses a header made with other -D
# macros). GCC 12 does not keep `#pragma GCC diagnostic` in a precompiled header (GCC bug
# 64117): libstdc++'s char_traits.h switches off -Wstringop-overflow, -Wstringop-overread and
# -Warray-bounds around its string copies that way, and without the pragmas -O3 reports false
# positives there; the targets that use the header get those three as options instead
# (SB_PCH_LOST_PRAGMAS).
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  option(SB_PCH "Shared precompiled headers for the common third-party headers" OFF)
else()
  set(SB_PCH OFF CACHE BOOL "Shared precompiled headers (GCC only)" FORCE)
endif()
set(SB_PCH_LOST_PRAGMAS -Wno-stringop-overflow -Wno-stringop-overread -Wno-array-bounds)
set(SB_PCH_HEADERS
    <algorithm> <array> <chrono> <cmath> <cstdint> <filesystem> <functional> <iostream> <map>
    <memory> <optional> <span> <sstream> <string> <string_view> <thread> <utility> <variant>
    <vector> <opencv2/core.hpp> <opencv2/imgproc.hpp>)
# ccache caches a file built with a precompiled header only when told to be sloppy about the
# header's macros and times (it is rebuilt in every fresh build folder).
if(SB_PCH AND CMAKE_CXX_COMPILER_LAUNCHER MATCHES "ccache")
  set(CMAKE_CXX_COMPILER_LAUNCHER ${CMAKE_COMMAND} -E env
      CCACHE_SLOPPINESS=pch_defines,time_macros,include_file_mtime,include_file_ctime
      ${CMAKE_CXX_COMPILER_LAUNCHER})
endif()
if(SB_PCH)
  # CONFIGURE writes only when the text changes (a rewrite would rebuild the headers).
  file(CONFIGURE OUTPUT ${CMAKE_BINARY_DIR}/sb_pch.cpp CONTENT "// the precompiled headers' host\n")
  add_library(sb_pch OBJECT ${CMAKE_BINARY_DIR}/sb_pch.cpp)
  target_link_libraries(sb_pch PRIVATE opencv_core opencv_imgproc)
  target_precompile_headers(sb_pch PRIVATE ${SB_PCH_HEADERS})
  if(SB_BUILD_TESTS)
    add_library(sb_pch_test OBJECT ${CMAKE_BINARY_DIR}/sb_pch.cpp)
    target_link_libraries(sb_pch_test PRIVATE opencv_core opencv_imgproc GTest::gtest)
    target_precompile_headers(sb_pch_test PRIVATE ${SB_PCH_HEADERS} <gtest/gtest.h>)
  endif()
  add_compile_options($<$<COMPILE_LANGUAGE:CXX>:-Winvalid-pch>)
endif()

# Build speed: unity builds. Every target's sources are compiled as one file (CMake's
# UNITY_BUILD, batch size 0), so OpenCV, Eigen, GoogleTest and the standard library are parsed
# once per library, program or test binary instead of once per source file. -DSB_UNITY=OFF
# compiles every file alone (quicker rebuilds of one edited file, and the check that each file
# includes what it uses). Names at file scope (anonymous namespaces, statics, using-directives,
# macros) must not clash between the files of one target. CMake leaves a file with its own
# COMPILE_OPTIONS/COMPILE_DEFINITIONS out of the unity file; SKIP_UNITY_BUILD_INCLUSION on a
# source leaves out any other.
option(SB_UNITY "Compile each target's sources as one translation unit" ON)
if(SB_UNITY)
  set(CMAKE_UNITY_BUILD ON)
  set(CMAKE_UNITY_BUILD_BATCH_SIZE 0)
  # GCC's -Wsubobject-linkage is about headers; a source file included into the unity file
  # counts as one, so every type in an anonymous namespace used by another type is reported.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    add_compile_options($<$<COMPILE_LANGUAGE:CXX>:-Wno-subobject-linkage>)
  endif()
endif()
# Build speed: the test binaries' own code (the test files, not the libraries they test) is
# compiled with -O1 in optimised builds: about half the compile time of -O3, and the code under
# test keeps the optimisation it ships with. -DSB_TEST_OPT=OFF keeps the build type's level.
option(SB_TEST_OPT "Compile test files with -O1 in Release builds" ON)
# Build speed: programs and test helpers whose speed nothing measures (no benchmark times them and
# no timed run starts them) are compiled with -O1 in Release builds, through sb_untimed() with
# the list at the end of the top CMakeLists.txt (CLI11 itself is compiled as at -O0 everywhere:
# common/util/cli11.hpp). -DSB_UNTIMED_OPT=OFF keeps the build type's level.
option(SB_UNTIMED_OPT "Compile programs and test helpers nothing times with -O1 in Release builds"
       ON)

# Build speed: CLI11 is included through common/util/cli11.hpp only, which compiles it without
# optimisation (a command line is parsed once per process). A direct include anywhere would
# compile it at the file's level again in every file of that target, so configuring stops on one.
# sb_cli11: what a target that parses a command line links (CLI11 and the folder of
# common/util/cli11.hpp).
add_library(sb_cli11 INTERFACE)
target_include_directories(sb_cli11 INTERFACE ${SB_SOURCE_ROOT}/components)
target_link_libraries(sb_cli11 INTERFACE CLI11::CLI11)
function(sb_check_cli11_includes)
  file(GLOB_RECURSE files ${SB_SOURCE_ROOT}/components/*.[ch]pp ${SB_SOURCE_ROOT}/tools/*.[ch]pp
       ${SB_SOURCE_ROOT}/tests/*.[ch]pp)
  foreach(f IN LISTS files)
    if(f MATCHES "/common/util/cli11\\.hpp$")
      continue()
    endif()
    file(STRINGS ${f} hits REGEX "^[ \t]*#[ \t]*include[ \t]*<CLI/")
    if(hits)
      message(FATAL_ERROR "${f} includes CLI11 directly; include \"common/util/cli11.hpp\" instead")
    endif()
  endforeach()
endfunction()
sb_check_cli11_includes()

# sb_untimed(TARGET...): -O1 for these targets in Release builds (SB_UNTIMED_OPT). Only for code
# no benchmark times and no timed run starts; names that are not targets here are ignored.
function(sb_untimed)
  if(NOT SB_UNTIMED_OPT)
    return()
  endif()
  foreach(t IN LISTS ARGN)
    if(TARGET ${t})
      target_compile_options(${t} PRIVATE $<$<CONFIG:Release>:-O1>)
    endif()
  endforeach()
endfunction()

# Adds every immediate sub-folder of DIR that has a CMakeLists.txt, so a new
# component or tool needs no edit of a shared file.
function(sb_add_subdirectories dir)
  file(GLOB children LIST_DIRECTORIES true RELATIVE ${CMAKE_CURRENT_SOURCE_DIR}/${dir}
       ${CMAKE_CURRENT_SOURCE_DIR}/${dir}/*)
  list(SORT children)
  foreach(child IN LISTS children)
    # SB_ONLY (a list of folder names) restricts the build to those folders, for quick
    # partial builds while other parts are being changed.
    if(SB_ONLY AND NOT child IN_LIST SB_ONLY)
      continue()
    endif()
    if(EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/${dir}/${child}/CMakeLists.txt)
      add_subdirectory(${dir}/${child})
    endif()
  endforeach()
endfunction()

# sb_add_library(NAME SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# A static library whose headers are included as "<component>/<...>.hpp"
# relative to INCLUDE_ROOT (default: the folder two levels up, i.e. components/).
function(sb_add_library name)
  cmake_parse_arguments(A "" "INCLUDE_ROOT" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(${name} STATIC ${A_SOURCES})
  if(NOT A_INCLUDE_ROOT)
    set(A_INCLUDE_ROOT ${SB_SOURCE_ROOT}/components)
  endif()
  target_include_directories(${name} PUBLIC ${A_INCLUDE_ROOT})
  target_link_libraries(${name} PUBLIC ${A_PUBLIC_DEPS} PRIVATE ${A_PRIVATE_DEPS})
endfunction()

# Each test binary that uses DDS gets its own domain id, allocated here at
# configure time, so tests running in parallel never see each other.
set_property(GLOBAL PROPERTY SB_NEXT_DOMAIN_ID 100)

# main() of every test binary (tests/support/gtest_main.cpp): exits 77 when every case that ran
# skipped, so ctest reports a GTEST_SKIP as skipped instead of passed.
if(SB_BUILD_TESTS)
  add_library(sb_gtest_main STATIC ${SB_SOURCE_ROOT}/tests/support/gtest_main.cpp)
  target_link_libraries(sb_gtest_main PUBLIC GTest::gtest)
endif()
# ThreadSanitizer build (-DSB_SANITIZE=thread): third-party races are suppressed, naming the
# library, in cmake/tsan_suppressions.txt. Every process a test starts inherits the options and
# writes its reports to <build>/tsan/report.<pid> (tools/tsan_tests.sh fails on any).
set(SB_TSAN_OPTIONS "TSAN_OPTIONS=suppressions=${SB_SOURCE_ROOT}/cmake/tsan_suppressions.txt \
second_deadlock_stack=1 log_path=${CMAKE_BINARY_DIR}/tsan/report")
if(SB_SANITIZE STREQUAL "thread")
  file(MAKE_DIRECTORY ${CMAKE_BINARY_DIR}/tsan)
endif()

# Build speed: grouped test binaries (SB_TEST_GROUPS, on). The tests of one area (a component
# under components/, or tools/, or tests/) are linked into a few shared executables
# (tests/sb_tests_AREA_N, at most SB_TEST_GROUP_FILES source files each), compiled as one unity
# file: GoogleTest, OpenCV and the standard library are then parsed and their inline code
# generated once per group instead of once per test, and there are fewer links. Each test keeps
# its ctest entry, with its own environment, domain id, timeout and labels: the entry runs the
# group with --sb_sources=FILE,... (tests/support/gtest_main.cpp), so only the cases defined in
# that test's files run. The test's name stays a target (building it builds its group), so
# `add_dependencies(NAME program)` keeps working. A test that needs its own compile definitions
# says ALONE. -DSB_TEST_GROUPS=OFF gives every test its own executable again.
option(SB_TEST_GROUPS "Link the tests of one area into a few shared executables" ON)
set(SB_TEST_GROUP_FILES 14 CACHE STRING "Most source files in one grouped test executable")

# sb_test_executable(NAME SOURCES DEPS ALONE OUT): creates (or finds) the executable that holds
# test NAME, adds SOURCES and DEPS to it; OUT gets its target name.
function(sb_test_executable name sources deps alone out)
  set(setup OFF)
  if(NOT SB_TEST_GROUPS OR alone)
    set(exe ${name})
    add_executable(${exe} ${sources})
    set(setup ON)
  else()
    # The area: components/X -> X, else the top folder (tools, tests).
    file(RELATIVE_PATH rel ${SB_SOURCE_ROOT} ${CMAKE_CURRENT_SOURCE_DIR})
    string(REPLACE "/" ";" parts "${rel}")
    list(GET parts 0 area)
    if(area STREQUAL "components")
      list(GET parts 1 area)
    elseif(area STREQUAL "tests")
      set(area system)
    endif()
    list(LENGTH sources n)
    get_property(index GLOBAL PROPERTY SB_TEST_GROUP_${area}_INDEX)
    get_property(files GLOBAL PROPERTY SB_TEST_GROUP_${area}_FILES)
    if(NOT index)
      set(index 1)
      set(files 0)
    endif()
    math(EXPR total "${files} + ${n}")
    if(files GREATER 0 AND total GREATER SB_TEST_GROUP_FILES)
      math(EXPR index "${index} + 1")
      set(files 0)
    endif()
    math(EXPR files "${files} + ${n}")
    set_property(GLOBAL PROPERTY SB_TEST_GROUP_${area}_INDEX ${index})
    set_property(GLOBAL PROPERTY SB_TEST_GROUP_${area}_FILES ${files})
    set(exe sb_tests_${area}_${index})
    if(NOT TARGET ${exe})
      add_executable(${exe})
      set(setup ON)
    endif()
    set(abs)
    foreach(s IN LISTS sources)
      get_filename_component(s ${s} ABSOLUTE BASE_DIR ${CMAKE_CURRENT_SOURCE_DIR})
      list(APPEND abs ${s})
    endforeach()
    target_sources(${exe} PRIVATE ${abs})
    # The test's name stays a target: building it builds the group, and what the test needs
    # built first (add_dependencies(NAME ...)) is built with `all`.
    add_custom_target(${name} ALL)
    add_dependencies(${name} ${exe})
  endif()
  target_link_libraries(${exe} PRIVATE ${deps})
  if(setup)
    target_link_libraries(${exe} PRIVATE sb_gtest_main GTest::gtest GTest::gmock)
    set_target_properties(${exe} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/tests)
    if(SB_TEST_OPT)
      target_compile_options(${exe} PRIVATE $<$<CONFIG:Release>:-O1>)
    endif()
    target_compile_definitions(${exe} PRIVATE
      SB_SHARED_DATA_DIR="${SB_SHARED_DATA_DIR}"
      SB_SOURCE_DIR="${SB_SOURCE_ROOT}"
      SB_BIN_DIR="${CMAKE_BINARY_DIR}/bin")
  endif()
  set(${out} ${exe} PARENT_SCOPE)
endfunction()

# sb_add_gtest(NAME SOURCES ... [DEPS ...] [DDS] [ALONE] [TIMEOUT s] [LABELS ...]
#              [SKIPPABLE SUFFIX FILTER [SUFFIX FILTER ...]])
# Builds a GoogleTest binary (or adds the test to a grouped one, SB_TEST_GROUPS) and registers
# it with ctest. With DDS the test
# gets STEREOBALL_DOMAIN (unique) and the loopback Cyclone DDS configuration.
# A test whose cases all skip is reported as skipped (exit 77). Cases that can skip while
# others in the test pass must be named with SKIPPABLE: each FILTER (a --gtest_filter
# pattern) becomes its own ctest entry NAME.SUFFIX (say in SUFFIX what it needs, e.g.
# needs_netem), and the entry NAME runs the rest. The entries of one test never run at the
# same time (they share its domain id and whatever else it uses). ALONE: its own executable
# (for a test that sets compile definitions of its own on target NAME).
function(sb_add_gtest name)
  if(NOT SB_BUILD_TESTS)
    return()
  endif()
  cmake_parse_arguments(A "DDS;ALONE" "TIMEOUT" "SOURCES;DEPS;LABELS;SKIPPABLE" ${ARGN})
  sb_test_executable(${name} "${A_SOURCES}" "${A_DEPS}" "${A_ALONE}" exe)
  # For sb_check_test_programs (cmake/TestPrograms.cmake): the files that may name programs.
  set(abs_sources)
  foreach(s IN LISTS A_SOURCES)
    get_filename_component(s ${s} ABSOLUTE BASE_DIR ${CMAKE_CURRENT_SOURCE_DIR})
    list(APPEND abs_sources ${s})
  endforeach()
  set_property(GLOBAL APPEND PROPERTY SB_GTESTS ${name})
  set_property(GLOBAL PROPERTY SB_GTEST_SOURCES_${name} ${abs_sources})
  # In a group, the entry runs the cases of this test's files only.
  set(run $<TARGET_FILE:${exe}> --gtest_color=no)
  if(NOT exe STREQUAL name)
    set(rel)
    foreach(s IN LISTS A_SOURCES)
      get_filename_component(s ${s} ABSOLUTE BASE_DIR ${CMAKE_CURRENT_SOURCE_DIR})
      file(RELATIVE_PATH s ${SB_SOURCE_ROOT} ${s})
      list(APPEND rel ${s})
    endforeach()
    list(JOIN rel "," rel)
    list(APPEND run --sb_sources=${rel})
  endif()
  if(NOT A_TIMEOUT)
    set(A_TIMEOUT 120)
  endif()
  # STEREOBALL_ENV_FILE empty: no test reads the host's /etc/stereoball/stereoball.env.
  set(env "SB_BIN_DIR=${CMAKE_BINARY_DIR}/bin" "SB_SOURCE_DIR=${SB_SOURCE_ROOT}"
      "STEREOBALL_ENV_FILE=")
  if(SB_SANITIZE STREQUAL "thread")
    list(APPEND env "${SB_TSAN_OPTIONS}")
  endif()
  if(A_DDS)
    get_property(domain GLOBAL PROPERTY SB_NEXT_DOMAIN_ID)
    math(EXPR next "${domain} + 1")
    set_property(GLOBAL PROPERTY SB_NEXT_DOMAIN_ID ${next})
    if(domain GREATER 230)
      message(FATAL_ERROR "Out of DDS domain ids for tests")
    endif()
    list(APPEND env "STEREOBALL_DOMAIN=${domain}"
         "CYCLONEDDS_URI=file://${SB_SOURCE_ROOT}/config/cyclonedds/loopback.xml")
    list(APPEND A_LABELS dds)
  endif()
  # The entries: NAME.SUFFIX per skippable filter, NAME for the rest.
  set(entries)
  set(excluded)
  list(LENGTH A_SKIPPABLE n)
  math(EXPR odd "${n} % 2")
  if(odd)
    message(FATAL_ERROR "sb_add_gtest(${name}): SKIPPABLE takes SUFFIX FILTER pairs")
  endif()
  while(A_SKIPPABLE)
    list(POP_FRONT A_SKIPPABLE suffix filter)
    add_test(NAME ${name}.${suffix} COMMAND ${run} --gtest_filter=${filter})
    list(APPEND entries ${name}.${suffix})
    list(APPEND excluded ${filter})
  endwhile()
  if(excluded)
    list(JOIN excluded ":" excluded)
    add_test(NAME ${name} COMMAND ${run} --gtest_filter=-${excluded})
    set_tests_properties(${name} ${entries} PROPERTIES RESOURCE_LOCK ${name})
  else()
    add_test(NAME ${name} COMMAND ${run})
  endif()
  # COST: with no timing history yet (a fresh clone), `ctest -j` starts the tests allowed the
  # longest first, so the long ones run beside the short ones instead of after them.
  set_tests_properties(${name} ${entries} PROPERTIES TIMEOUT ${A_TIMEOUT} ENVIRONMENT "${env}"
                       LABELS "${A_LABELS}" SKIP_RETURN_CODE 77 COST ${A_TIMEOUT})
endfunction()

# True (in out) when opts has an option that changes what GCC accepts in a precompiled header
# and that the headers were not made with (the project-wide options are in both).
function(sb_pch_incompatible opts out)
  get_target_property(common sb_pch COMPILE_OPTIONS)
  set(bad FALSE)
  foreach(opt IN LISTS opts)
    if(NOT opt IN_LIST common AND opt MATCHES "^-(std=|m|f(no-)?sanitize|D|U|include)")
      set(bad TRUE)
    endif()
  endforeach()
  set(${out} ${bad} PARENT_SCOPE)
endfunction()

# Gives every C++ target below dir (default: the whole project) a shared precompiled header.
function(sb_use_precompiled_headers)
  if(NOT SB_PCH)
    return()
  endif()
  set(dir ${ARGV0})
  if(NOT dir)
    set(dir ${CMAKE_SOURCE_DIR})
  endif()
  get_property(targets DIRECTORY ${dir} PROPERTY BUILDSYSTEM_TARGETS)
  foreach(t IN LISTS targets)
    get_target_property(type ${t} TYPE)
    get_target_property(imported ${t} IMPORTED)
    if(NOT type MATCHES "^(EXECUTABLE|STATIC_LIBRARY|SHARED_LIBRARY|MODULE_LIBRARY|OBJECT_LIBRARY)$"
       OR imported OR t MATCHES "^sb_pch(_test)?$")
      continue()
    endif()
    get_target_property(off ${t} DISABLE_PRECOMPILE_HEADERS)
    get_target_property(own ${t} PRECOMPILE_HEADERS)
    get_target_property(opts ${t} COMPILE_OPTIONS)
    sb_pch_incompatible("${opts}" bad)
    if(off OR own OR bad)
      continue()
    endif()
    get_target_property(sources ${t} SOURCES)
    get_target_property(src_dir ${t} SOURCE_DIR)
    set(cxx FALSE)
    set(has_c FALSE)
    foreach(s IN LISTS sources)
      if(s MATCHES "^\\$<")
        continue()
      endif()
      if(NOT IS_ABSOLUTE ${s})
        set(s ${src_dir}/${s})
      endif()
      if(s MATCHES "\\.c$")
        # C files (the generated message types in sb_idl): CMake would look for a C header
        # in sb_pch, which has none, so such a target is left out.
        set(has_c TRUE)
      endif()
      if(NOT s MATCHES "\\.(cpp|cc|cxx)$")
        continue()
      endif()
      set(cxx TRUE)
      get_source_file_property(sopts ${s} TARGET_DIRECTORY ${t} COMPILE_OPTIONS)
      sb_pch_incompatible("${sopts}" sbad)
      if(sbad)
        set_source_files_properties(${s} TARGET_DIRECTORY ${t} PROPERTIES
                                    SKIP_PRECOMPILE_HEADERS ON)
      endif()
    endforeach()
    if(NOT cxx OR has_c)
      continue()
    endif()
    get_target_property(libs ${t} LINK_LIBRARIES)
    if(TARGET sb_pch_test AND "${libs}" MATCHES "(^|;)(GTest::[A-Za-z_]+|sb_gtest_main)(;|$)")
      target_precompile_headers(${t} REUSE_FROM sb_pch_test)
    else()
      target_precompile_headers(${t} REUSE_FROM sb_pch)
    endif()
    # Where a file cannot use the precompiled header, the headers are read as text.
    target_include_directories(${t} SYSTEM PRIVATE ${OpenCV_INCLUDE_DIRS})
    target_compile_options(${t} PRIVATE "$<$<COMPILE_LANGUAGE:CXX>:${SB_PCH_LOST_PRAGMAS}>")
  endforeach()
  get_property(subdirs DIRECTORY ${dir} PROPERTY SUBDIRECTORIES)
  foreach(sub IN LISTS subdirs)
    sb_use_precompiled_headers(${sub})
  endforeach()
endfunction()
