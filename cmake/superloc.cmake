# Build helpers shared by every SuperLoc target.

# C++17, warnings, optional -Werror and sanitizers. No -march flag tuned to this CPU: MRPT, PCL and Ceres
# are built without it, and a differing Eigen alignment crashes at run time. A flag passed in by
# the user (CMAKE_CXX_FLAGS*) is refused here, at configure time, rather than crashing later.
foreach(_flags_var CMAKE_CXX_FLAGS CMAKE_CXX_FLAGS_RELEASE CMAKE_CXX_FLAGS_RELWITHDEBINFO CMAKE_CXX_FLAGS_DEBUG
                   CMAKE_C_FLAGS)
  # The same flags as the build's compile-command check (cmake/check_no_cpu_flags.cmake): any
  # -march=..., -mtune=native, -mavx*, -mfma.
  if("${${_flags_var}}" MATCHES "-m(arch=[^ ]+|tune=native|avx|fma)")
    message(FATAL_ERROR "${_flags_var} holds a CPU-specific flag (${${_flags_var}}): MRPT, PCL and Ceres from "
                        "Debian are built without it, and Eigen objects of differing alignment crash at run time")
  endif()
endforeach()
function(superloc_target_options target)
  target_compile_features(${target} PUBLIC cxx_std_17)
  target_compile_options(${target} PRIVATE -Wall -Wextra)
  if(SUPERLOC_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
  if(SUPERLOC_SANITIZE)
    target_compile_options(${target} PRIVATE -fsanitize=address,undefined -fno-omit-frame-pointer)
    target_link_options(${target} PUBLIC -fsanitize=address,undefined)
    # Eigen stops trusting malloc's 16-byte alignment under ASan (__SANITIZE_ADDRESS__) and
    # switches to its hand-made aligned allocator; PCL/MRPT/Ceres, built without ASan, allocate
    # with plain malloc, so an Eigen vector created in PCL and freed in our code (NDT's voxel
    # leaves) is freed the wrong way. Keep our code on the libraries' allocator.
    target_compile_definitions(${target} PRIVATE EIGEN_MALLOC_ALREADY_ALIGNED=1)
    # GCC 12 at -O1 with the sanitizers reports libstdc++'s own std::regex internals as "maybe
    # uninitialized" (std::function moved inside _NFA::_M_insert_subexpr_*; tests that use
    # std::regex, e.g. test_structure.cpp): a false positive in the system header, not our code.
    if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
      target_compile_options(${target} PRIVATE -Wno-maybe-uninitialized)
    endif()
  endif()
endfunction()

# superloc_module(<name> [DEPS <public libs>...] [PRIVATE_DEPS <libs>...])
# Builds modules/<name>/src/*.cpp into the static library superloc::<name>.
function(superloc_module name)
  cmake_parse_arguments(A "" "" "DEPS;PRIVATE_DEPS" ${ARGN})
  file(GLOB srcs CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/*.cpp)
  add_library(superloc_${name} STATIC ${srcs})
  add_library(superloc::${name} ALIAS superloc_${name})
  target_include_directories(superloc_${name} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(superloc_${name} PUBLIC ${A_DEPS} PRIVATE ${A_PRIVATE_DEPS})
  superloc_target_options(superloc_${name})
  # Installed as lib/libsuperloc_<name>.a + include/superloc/<name>/, exported as superloc::<name>
  # (cmake/superloc-install.cmake writes the package configuration).
  set_target_properties(superloc_${name} PROPERTIES EXPORT_NAME ${name})
  install(TARGETS superloc_${name} EXPORT superloc-targets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev)
  install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
    COMPONENT dev)
endfunction()

# superloc_app(<exe-name> <source> [DEPS <libs>...])
function(superloc_app name src)
  cmake_parse_arguments(A "" "" "DEPS" ${ARGN})
  add_executable(${name} ${src})
  target_link_libraries(${name} PRIVATE ${A_DEPS})
  # All apps side by side in build/bin: superloc-bench runs its siblings.
  set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/bin)
  superloc_target_options(${name})
  install(TARGETS ${name} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT apps)
endfunction()

# superloc_test(<module> [DEPS <libs>...]): tests/<module>/test_*.cpp -> test_<module>.
function(superloc_test module)
  cmake_parse_arguments(A "" "" "DEPS" ${ARGN})
  file(GLOB srcs CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/${module}/test_*.cpp)
  if(NOT srcs)
    return()
  endif()
  add_executable(test_${module} ${srcs})
  target_link_libraries(test_${module} PRIVATE ${A_DEPS} superloc_testing GTest::gtest_main)
  superloc_target_options(test_${module})
  gtest_discover_tests(test_${module}
    WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR}
    DISCOVERY_TIMEOUT 120
    PROPERTIES LABELS ${module})
endfunction()
