# What `cmake --install build --prefix X` installs (docs/install.md):
#
#   bin/psim                                   the program
#   bin/psim-plot, bin/psim-animate            charts and animations of runs
#                                              (scripts/psim-plot, scripts/animate)
#   lib/libpsim.so.0.2.0, libpsim.so.0, libpsim.so
#                                              the shared library (SONAME
#                                              libpsim.so.0) and its links
#   lib/libpsim.a                              the static library
#   include/psim/*.h                           their API
#   lib/cmake/psim/psim{Config,ConfigVersion,Targets*}.cmake
#                                              find_package(psim): psim::psim,
#                                              psim::psim_shared, psim::psim_static
#   lib/pkgconfig/psim.pc                      pkg-config psim
#   share/man/man1/psim.1                      the man page
#   share/bash-completion/completions/psim     the bash completion
#   share/doc/psim/*.md, img/, ...             docs/ and README.md
#
# (lib, include, share: GNUInstallDirs' CMAKE_INSTALL_LIBDIR and the others.)
# Nothing installed names the build tree or the prefix: the CMake files
# find the prefix from their own place, psim.pc from ${pcfiledir}, so the
# installed tree can be moved.  The man page and the completion are written
# at build time from the built psim's own --help (cmake/psim_docs.py).
include(CMakePackageConfigHelpers)

set(PSIM_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/psim)

# A sanitizer build's library holds instrumented code, which links only
# with the sanitizer's runtime: the installed package asks for it (in the
# build tree add_link_options already does).
if(PSIM_SANITIZE)
  foreach(lib psimlib psim_shared)
    target_link_options(${lib} INTERFACE "$<INSTALL_INTERFACE:-fsanitize=${PSIM_SANITIZE}>")
  endforeach()
endif()

install(TARGETS psim RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT Runtime)
# The shared library libpsim.so.0.2.0 and its SONAME's link libpsim.so.0
# (what programs load) are the component Library; libpsim.so (what -lpsim
# links) goes with the Development files.
install(TARGETS psimlib psim_shared psim_default EXPORT psimTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT Development
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT Library
                NAMELINK_COMPONENT Development)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/psim
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT Development
        FILES_MATCHING PATTERN "*.h")

# ---- CMake package: find_package(psim CONFIG), target psim::psim -----------
install(EXPORT psimTargets NAMESPACE psim:: DESTINATION ${PSIM_CMAKE_DIR}
        COMPONENT Development)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/psimConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/package/psimConfig.cmake
                              INSTALL_DESTINATION ${PSIM_CMAKE_DIR})
# 0.x: a new minor version may change the API
write_basic_package_version_file(${PROJECT_BINARY_DIR}/package/psimConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/package/psimConfig.cmake
              ${PROJECT_BINARY_DIR}/package/psimConfigVersion.cmake
        DESTINATION ${PSIM_CMAKE_DIR} COMPONENT Development)

# ---- pkg-config: psim.pc ----------------------------------------------------
# `pkg-config --libs psim` gives -L${libdir} -lpsim, which links
# libpsim.so: it names its own libraries (DT_NEEDED).  What libpsim.a
# links goes to Libs.private (pkg-config --static).  hwloc is named by the
# flags its own .pc file gives for linking its shared library (-lhwloc),
# not as Requires.private: with --static that would pull in hwloc's own
# Libs.private (Debian's names -ludev, whose libudev.so only libudev-dev
# has), flags for linking hwloc itself statically, which no one asked for.
# OpenMP by the compiler's flag (-fopenmp: the same compiler family must
# link, for its OpenMP runtime).  A sanitizer build's libraries, shared
# and static, hold instrumented code: every program that links them needs
# the sanitizer, in Libs.  (CMake's pkg-config call keeps -L of the
# compiler's own directories: dropped, as pkg-config itself drops them.)
separate_arguments(PSIM_PC_OPENMP UNIX_COMMAND "${OpenMP_C_FLAGS}")
set(PSIM_PC_LIBS_PRIVATE ${PSIM_PC_OPENMP} -lm)
foreach(flag IN LISTS psim_hwloc_LDFLAGS)
  string(REGEX REPLACE "^-L" "" dir "${flag}")
  if(NOT (flag MATCHES "^-L" AND dir IN_LIST CMAKE_C_IMPLICIT_LINK_DIRECTORIES))
    list(APPEND PSIM_PC_LIBS_PRIVATE "${flag}")
  endif()
endforeach()
if(PSIM_HAVE_CUDA)   # (cmake/cuda.cmake)
  list(APPEND PSIM_PC_LIBS_PRIVATE ${PSIM_CUDA_PC_LIBS})
endif()
foreach(lib IN LISTS CMAKE_DL_LIBS)
  list(APPEND PSIM_PC_LIBS_PRIVATE -l${lib})
endforeach()
set(PSIM_PC_LIBS "")
if(PSIM_SANITIZE)
  set(PSIM_PC_LIBS " -fsanitize=${PSIM_SANITIZE}")
endif()
if(PSIM_LIKWID)
  list(APPEND PSIM_PC_LIBS_PRIVATE -llikwid)
endif()
if(PSIM_MPI)   # MPI's libraries by their full paths (libpsim.a's runs over ranks)
  list(APPEND PSIM_PC_LIBS_PRIVATE ${MPI_C_LIBRARIES})
endif()
list(REMOVE_DUPLICATES PSIM_PC_LIBS_PRIVATE)
list(JOIN PSIM_PC_LIBS_PRIVATE " " PSIM_PC_LIBS_PRIVATE)
# prefix, from where psim.pc lies: ${pcfiledir}/../.. for lib/pkgconfig
set(PSIM_PC_DIR ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
if(IS_ABSOLUTE "${CMAKE_INSTALL_LIBDIR}" OR IS_ABSOLUTE "${CMAKE_INSTALL_INCLUDEDIR}")
  message(FATAL_ERROR "psim.pc: CMAKE_INSTALL_LIBDIR and CMAKE_INSTALL_INCLUDEDIR must be "
                      "relative to the prefix (they are '${CMAKE_INSTALL_LIBDIR}', "
                      "'${CMAKE_INSTALL_INCLUDEDIR}')")
endif()
file(RELATIVE_PATH PSIM_PC_TO_PREFIX /prefix/${PSIM_PC_DIR} /prefix)
string(REGEX REPLACE "/$" "" PSIM_PC_TO_PREFIX "${PSIM_PC_TO_PREFIX}")
configure_file(${PROJECT_SOURCE_DIR}/cmake/psim.pc.in ${PROJECT_BINARY_DIR}/package/psim.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/package/psim.pc DESTINATION ${PSIM_PC_DIR}
        COMPONENT Development)

# ---- man page and bash completion, from the built psim's --help -------------
# python3 with its standard library only (a dependency already:
# scripts/install-deps.sh, tests/stability)
find_package(Python3 REQUIRED COMPONENTS Interpreter)
set(PSIM_MAN ${PROJECT_BINARY_DIR}/doc/psim.1)
set(PSIM_COMPLETION ${PROJECT_BINARY_DIR}/doc/psim.bash)
add_custom_command(
  OUTPUT ${PSIM_MAN} ${PSIM_COMPLETION}
  COMMAND Python3::Interpreter ${PROJECT_SOURCE_DIR}/cmake/psim_docs.py
          --psim $<TARGET_FILE:psim> --version ${PROJECT_VERSION}
          --description "${PROJECT_DESCRIPTION}"
          --man ${PSIM_MAN} --man-template ${PROJECT_SOURCE_DIR}/cmake/psim-man.in
          --docdir ${CMAKE_INSTALL_DOCDIR}
          --completion-template ${PROJECT_SOURCE_DIR}/cmake/psim-completion.bash.in
          --completion ${PSIM_COMPLETION}
  DEPENDS psim ${PROJECT_SOURCE_DIR}/cmake/psim_docs.py
          ${PROJECT_SOURCE_DIR}/cmake/psim-completion.bash.in
          ${PROJECT_SOURCE_DIR}/cmake/psim-man.in
  COMMENT "psim.1 and the bash completion from psim --help" VERBATIM)
add_custom_target(psim_docs ALL DEPENDS ${PSIM_MAN} ${PSIM_COMPLETION})
install(FILES ${PSIM_MAN} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1 COMPONENT Runtime)
install(FILES ${PSIM_COMPLETION} DESTINATION ${CMAKE_INSTALL_DATADIR}/bash-completion/completions
        RENAME psim COMPONENT Runtime)

# ---- the documents: docs/ as share/doc/psim, README.md beside them ----------
# README.md's links to docs/NAME.md are made NAME.md, where those lie once
# installed; docs/ keeps its folders (img/, ...), which its pages link to.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR}
        COMPONENT Runtime)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/README.md)
file(READ ${PROJECT_SOURCE_DIR}/README.md psim_readme)
string(REPLACE "](docs/" "](" psim_readme "${psim_readme}")
file(WRITE ${PROJECT_BINARY_DIR}/doc/README.md "${psim_readme}")
install(FILES ${PROJECT_BINARY_DIR}/doc/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR}
        COMPONENT Runtime)

# ---- the scripts: charts (psim-plot) and animations (psim-animate) of runs ---
install(PROGRAMS ${PROJECT_SOURCE_DIR}/scripts/psim-plot
        DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT Runtime)
install(PROGRAMS ${PROJECT_SOURCE_DIR}/scripts/animate
        DESTINATION ${CMAKE_INSTALL_BINDIR} RENAME psim-animate COMPONENT Runtime)
