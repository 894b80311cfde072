# CTest driver (tests/CMakeLists.txt, test Install.ConsumerProject): installs the current build
# into a fresh prefix, configures and builds tests/consumer against it with find_package(superloc)
# and runs the consumer. Arguments (-D): BUILD_DIR, SOURCE_DIR, WORK_DIR, GENERATOR, CXX, C.
foreach(v BUILD_DIR SOURCE_DIR WORK_DIR GENERATOR CXX)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "run_consumer_test.cmake: -D${v}=... missing")
  endif()
endforeach()

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}\n${err}")
  endif()
  set(last_output "${out}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
run("cmake --install" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
foreach(f lib/cmake/superloc/superloc-config.cmake lib/cmake/superloc/superloc-config-version.cmake
          lib/libsuperloc_localization.a include/superloc/localization/localizer.h
          bin/superloc-localize share/superloc/ini/localize.ini)
  if(NOT EXISTS ${prefix}/${f})
    message(FATAL_ERROR "not installed: ${prefix}/${f}")
  endif()
endforeach()

set(c_arg)
if(C)
  set(c_arg -DCMAKE_C_COMPILER=${C})
endif()
run("configure the consumer" ${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${WORK_DIR}/build
    -G ${GENERATOR} -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix}
    -DCMAKE_CXX_COMPILER=${CXX} ${c_arg})
run("build the consumer" ${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run("run the consumer" ${WORK_DIR}/build/superloc-consumer)
message(STATUS "${last_output}")
if(NOT last_output MATCHES "PriorMap: [1-9][0-9]* points")
  message(FATAL_ERROR "unexpected consumer output: ${last_output}")
endif()
