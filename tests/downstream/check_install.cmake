# The suite's Downstream.BuildsAgainstInstalledPrefix (tests/CMakeLists.txt): installs the
# build into a fresh prefix and uses it as an application outside the project would.
#   1. the prefix holds the command, libdthex_core.a, the package files and every header of
#      core/FOLDER and modules/ as include/dthex/FOLDER/NAME, as files (no symlink), and
#      nothing installed names the source or build tree;
#   2. one file including every header compiles with pkg-config's Cflags alone;
#   3. tests/downstream configures with find_package(om_dthex) from the prefix alone,
#      builds, and its two programs pass on bundled meshes;
#   4. mesh_with_core.cpp compiles and links through pkg-config (--static) and passes.
# Arguments (-D): SOURCE_DIR, BINARY_DIR, WORK_DIR, GENERATOR, C_COMPILER, CXX_COMPILER,
# COMPILER_LAUNCHER (may be empty), PKG_CONFIG.
cmake_minimum_required(VERSION 3.20)

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT code EQUAL 0)
    string(REPLACE ";" " " command "${ARGN}")
    message(FATAL_ERROR "failed (${code}): ${command}\n${out}\n${err}")
  endif()
  set(run_output "${out}" PARENT_SCOPE)
endfunction()

set(prefix ${WORK_DIR}/prefix)
file(REMOVE_RECURSE ${prefix} ${WORK_DIR}/build ${WORK_DIR}/pkg-config)
file(MAKE_DIRECTORY ${WORK_DIR}/pkg-config)

# 1. The install tree.
run(${CMAKE_COMMAND} --install ${BINARY_DIR} --prefix ${prefix})
foreach(file bin/om_dthex lib/libdthex_core.a lib/cmake/om_dthex/om_dthexConfig.cmake
        lib/cmake/om_dthex/om_dthexConfigVersion.cmake lib/cmake/om_dthex/om_dthexTargets.cmake
        lib/pkgconfig/om_dthex.pc)
  if(NOT EXISTS ${prefix}/${file})
    message(FATAL_ERROR "not installed: ${file}")
  endif()
endforeach()
file(GLOB installed_programs RELATIVE ${prefix}/bin ${prefix}/bin/*)
if(NOT installed_programs STREQUAL "om_dthex")
  message(FATAL_ERROR "bin/ should hold only om_dthex, holds: ${installed_programs}")
endif()
file(GLOB_RECURSE expected RELATIVE ${SOURCE_DIR}/core ${SOURCE_DIR}/core/*.h)
file(GLOB modules RELATIVE ${SOURCE_DIR} ${SOURCE_DIR}/modules/*.hh)
list(APPEND expected ${modules})
file(GLOB_RECURSE installed RELATIVE ${prefix}/include/dthex ${prefix}/include/dthex/*)
list(SORT expected)
list(SORT installed)
if(NOT installed STREQUAL expected)
  message(FATAL_ERROR "include/dthex differs from core/ and modules/:\n"
                      "installed: ${installed}\nexpected: ${expected}")
endif()
file(GLOB_RECURSE everything LIST_DIRECTORIES true ${prefix}/*)
foreach(path ${everything})
  if(IS_SYMLINK ${path})
    message(FATAL_ERROR "the install tree holds a symlink: ${path}")
  endif()
endforeach()
file(GLOB_RECURSE package_files ${prefix}/lib/cmake/*.cmake ${prefix}/lib/pkgconfig/*.pc
     ${prefix}/include/*)
foreach(file ${package_files})
  file(READ ${file} text)
  foreach(tree ${SOURCE_DIR} ${BINARY_DIR})
    string(FIND "${text}" "${tree}" at)
    if(NOT at EQUAL -1)
      message(FATAL_ERROR "${file} names ${tree}")
    endif()
  endforeach()
endforeach()

# 2. Every header, with pkg-config's flags only.
set(ENV{PKG_CONFIG_PATH} ${prefix}/lib/pkgconfig)
run(${PKG_CONFIG} --cflags om_dthex)
separate_arguments(cflags UNIX_COMMAND "${run_output}")
run(${PKG_CONFIG} --libs --static om_dthex)
separate_arguments(libs UNIX_COMMAND "${run_output}")
set(compiler ${COMPILER_LAUNCHER} ${CXX_COMPILER})
set(all_headers "")
foreach(header ${expected})
  string(APPEND all_headers "#include <dthex/${header}>\n")
endforeach()
file(WRITE ${WORK_DIR}/pkg-config/all_headers.cpp "${all_headers}")
run(${compiler} -std=c++17 -c ${cflags} ${WORK_DIR}/pkg-config/all_headers.cpp
    -o ${WORK_DIR}/pkg-config/all_headers.o)

# 3. The CMake package, from the prefix alone. No build type: unoptimized, the programs
# compile in half the time and still run in a fraction of a second.
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/downstream -B ${WORK_DIR}/build -G ${GENERATOR}
    -DCMAKE_BUILD_TYPE= -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF
    -DCMAKE_C_COMPILER=${C_COMPILER} -DCMAKE_CXX_COMPILER=${CXX_COMPILER}
    -DCMAKE_CXX_COMPILER_LAUNCHER=${COMPILER_LAUNCHER})
file(STRINGS ${WORK_DIR}/build/CMakeCache.txt package_dir REGEX "^om_dthex_DIR:")
if(NOT package_dir STREQUAL "om_dthex_DIR:PATH=${prefix}/lib/cmake/om_dthex")
  message(FATAL_ERROR "find_package(om_dthex) did not take the prefix's package: ${package_dir}")
endif()
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run(${WORK_DIR}/build/decimate_with_modules ${SOURCE_DIR}/meshes/sphere728.off)
message(STATUS "${run_output}")
run(${WORK_DIR}/build/mesh_with_core ${SOURCE_DIR}/meshes/icosahedron.off ${WORK_DIR}/build/icosahedron.exo)
message(STATUS "${run_output}")

# 4. pkg-config: the core program compiled and linked from the .pc file's flags.
run(${compiler} -std=c++17 ${cflags} ${SOURCE_DIR}/tests/downstream/mesh_with_core.cpp
    -o ${WORK_DIR}/pkg-config/mesh_with_core ${libs})
run(${WORK_DIR}/pkg-config/mesh_with_core ${SOURCE_DIR}/meshes/icosahedron.off
    ${WORK_DIR}/pkg-config/icosahedron.exo)
message(STATUS "pkg-config build: ${run_output}")
