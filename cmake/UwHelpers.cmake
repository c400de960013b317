# uw_add_library(NAME scene SRCS a.cc b.cc DEPS uw::util Eigen3::Eigen)
# Creates target uw_<NAME> with the alias uw::<NAME>. Headers are included
# from the repository root: #include "colmap_plugins/scene/model.h".
function(uw_add_library)
  cmake_parse_arguments(ARG "" "NAME" "SRCS;DEPS" ${ARGN})
  add_library(uw_${ARG_NAME} ${ARG_SRCS})
  add_library(uw::${ARG_NAME} ALIAS uw_${ARG_NAME})
  target_include_directories(uw_${ARG_NAME} PUBLIC ${PROJECT_SOURCE_DIR})
  target_link_libraries(uw_${ARG_NAME} PUBLIC ${ARG_DEPS})
endfunction()

# uw_add_test_library(NAME calibration_testing SRCS x_testing.cc DEPS ...)
# A library only tests link: fixtures that may use the simulator (sim/,
# experiments/) and GoogleTest. Its files are named *_testing.{h,cc} or live
# in tests/support/, which scripts/check_layering.py treats as test code.
function(uw_add_test_library)
  cmake_parse_arguments(ARG "" "NAME" "SRCS;DEPS" ${ARGN})
  uw_add_library(NAME ${ARG_NAME} SRCS ${ARG_SRCS} DEPS ${ARG_DEPS})
  set_target_properties(uw_${ARG_NAME} PROPERTIES UW_TEST_ONLY TRUE)
endfunction()

# uw_add_header_library(NAME cameras DEPS Eigen3::Eigen)
function(uw_add_header_library)
  cmake_parse_arguments(ARG "" "NAME" "DEPS" ${ARGN})
  add_library(uw_${ARG_NAME} INTERFACE)
  add_library(uw::${ARG_NAME} ALIAS uw_${ARG_NAME})
  target_include_directories(uw_${ARG_NAME} INTERFACE ${PROJECT_SOURCE_DIR})
  target_link_libraries(uw_${ARG_NAME} INTERFACE ${ARG_DEPS})
endfunction()

# uw_add_test(NAME model_io_test SRCS model_io_test.cc DEPS uw::scene
#             [LABELS unit] [FIXTURES fixture_name])
# A GoogleTest executable whose cases are registered one by one with CTest.
# The default label is "unit"; scripts/test.sh runs everything not labelled
# "heavy" (scripts/bench.sh runs those).
function(uw_add_test)
  cmake_parse_arguments(ARG "" "NAME" "SRCS;DEPS;LABELS;FIXTURES" ${ARGN})
  if(NOT ARG_LABELS)
    set(ARG_LABELS unit)
  endif()
  add_executable(${ARG_NAME} ${ARG_SRCS})
  target_link_libraries(${ARG_NAME} PRIVATE ${ARG_DEPS} GTest::gtest
                                            GTest::gtest_main)
  set(properties LABELS "${ARG_LABELS}")
  if(ARG_FIXTURES)
    list(APPEND properties FIXTURES_REQUIRED "${ARG_FIXTURES}")
  endif()
  gtest_discover_tests(${ARG_NAME}
    PROPERTIES ${properties}
    DISCOVERY_TIMEOUT 60)
endfunction()

# uw_add_executable(NAME uwcolmap SRCS main.cc DEPS uw::scene)
function(uw_add_executable)
  cmake_parse_arguments(ARG "" "NAME" "SRCS;DEPS" ${ARGN})
  add_executable(${ARG_NAME} ${ARG_SRCS})
  target_link_libraries(${ARG_NAME} PRIVATE ${ARG_DEPS})
  set_target_properties(${ARG_NAME} PROPERTIES RUNTIME_OUTPUT_DIRECTORY
                                               ${PROJECT_BINARY_DIR}/bin)
endfunction()

# uw_check_no_test_library(uwcolmap laserscale ...)
# Fails the configuration if a program links, directly or through its
# libraries, a library declared with uw_add_test_library: fixtures may use
# the simulator, and no program may depend on it through them.
function(uw_check_no_test_library)
  foreach(program IN LISTS ARGN)
    set(pending ${program})
    set(seen "")
    while(pending)
      list(POP_FRONT pending target)
      if(NOT TARGET "${target}" OR "${target}" IN_LIST seen)
        continue()
      endif()
      list(APPEND seen "${target}")
      get_target_property(aliased ${target} ALIASED_TARGET)
      if(aliased)
        list(APPEND pending ${aliased})
        continue()
      endif()
      get_target_property(test_only ${target} UW_TEST_ONLY)
      if(test_only)
        message(FATAL_ERROR "${program} links the test-only library ${target}")
      endif()
      get_target_property(type ${target} TYPE)
      if(NOT type STREQUAL "INTERFACE_LIBRARY")
        get_target_property(libraries ${target} LINK_LIBRARIES)
        if(libraries)
          list(APPEND pending ${libraries})
        endif()
      endif()
      get_target_property(interface ${target} INTERFACE_LINK_LIBRARIES)
      if(interface)
        list(APPEND pending ${interface})
      endif()
    endwhile()
  endforeach()
endfunction()
