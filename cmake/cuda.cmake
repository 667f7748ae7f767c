# The CUDA path of psim (docs/gpu.md), included by the top CMakeLists.txt.
#
# PSIM_CUDA: AUTO (the default) builds it where nvcc is found, on PATH or
# under /usr/local/cuda; ON fails without nvcc; OFF never looks.  Sets
# PSIM_HAVE_CUDA, and defines psim_cuda_attach (the .cu sources of every
# model folder into an object target) and psim_cuda_link (the CUDA runtime
# into the libraries).
string(TOUPPER "${PSIM_CUDA}" psim_cuda_mode)
if(NOT psim_cuda_mode MATCHES "^(AUTO|ON|OFF)$")
  message(FATAL_ERROR "PSIM_CUDA is '${PSIM_CUDA}': ON, OFF or AUTO")
endif()
set(PSIM_HAVE_CUDA OFF)
if(NOT psim_cuda_mode STREQUAL "OFF" AND (PSIM_SANITIZE OR PSIM_FUZZ))
  # (why: the comment above include(cmake/cuda.cmake))
  if(psim_cuda_mode STREQUAL "ON")
    message(FATAL_ERROR "PSIM_CUDA=ON and PSIM_SANITIZE/PSIM_FUZZ: sanitizer and fuzz "
                        "builds check the C code only; build the CUDA path in a plain build")
  endif()
  message(STATUS "CUDA path: off in sanitizer and fuzz builds")
  set(psim_cuda_mode OFF)
endif()
if(NOT psim_cuda_mode STREQUAL "OFF")
  if(NOT CMAKE_CUDA_COMPILER AND NOT DEFINED ENV{CUDACXX})
    find_program(psim_nvcc nvcc)
    if(NOT psim_nvcc AND EXISTS /usr/local/cuda/bin/nvcc)
      set(psim_nvcc /usr/local/cuda/bin/nvcc)
    endif()
    if(psim_nvcc)
      set(CMAKE_CUDA_COMPILER ${psim_nvcc})
    endif()
  endif()
  include(CheckLanguage)
  check_language(CUDA)
  if(CMAKE_CUDA_COMPILER)
    # H100/H200 (sm_90) machine code and compute_90 PTX for later GPUs;
    # -DCMAKE_CUDA_ARCHITECTURES=... for others
    if(NOT DEFINED CMAKE_CUDA_ARCHITECTURES)
      set(CMAKE_CUDA_ARCHITECTURES 90)
    endif()
    enable_language(CUDA)
    find_package(CUDAToolkit REQUIRED)
    set(PSIM_HAVE_CUDA ON)
    message(STATUS "CUDA path: on (${CMAKE_CUDA_COMPILER}, architectures ${CMAKE_CUDA_ARCHITECTURES})")
  elseif(psim_cuda_mode STREQUAL "ON")
    message(FATAL_ERROR "PSIM_CUDA=ON but no nvcc was found (on PATH or as "
                        "/usr/local/cuda/bin/nvcc): set CUDACXX or CMAKE_CUDA_COMPILER, "
                        "or configure with -DPSIM_CUDA=OFF")
  else()
    message(STATUS "CUDA path: off (no nvcc)")
  endif()
endif()

# The flags of every .cu object, in place of the C objects' (which nvcc
# does not take): C++17; no fused multiply-add (a*b+c must round twice, as
# in the C code, -ffp-contract=off); IEEE division and square root, no
# fast math; every warning, an error with PSIM_WERROR.
set(PSIM_CUDA_FLAGS --fmad=false --prec-div=true --prec-sqrt=true --ftz=false
    -Xcompiler=-fno-omit-frame-pointer,-ffp-contract=off,-fno-math-errno,-fPIC
    -Xcompiler=-Wall,-Wextra -Wno-deprecated-gpu-targets)
if(PSIM_WERROR)
  list(APPEND PSIM_CUDA_FLAGS -Werror=all-warnings)
endif()

# psim_cuda_objects: the .cu sources of every model folder, with
# PSIM_CUDA_FLAGS alone (not the C objects' flags); c_objects, the C
# objects, get PSIM_HAVE_CUDA and the CUDA runtime's headers.
function(psim_cuda_attach c_objects)
  file(GLOB cu CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/models/*/*.cu)
  add_library(psim_cuda_objects OBJECT ${cu})
  set_target_properties(psim_cuda_objects PROPERTIES
                        COMPILE_OPTIONS "${PSIM_CUDA_FLAGS}"
                        POSITION_INDEPENDENT_CODE ON
                        CUDA_VISIBILITY_PRESET hidden
                        CUDA_STANDARD 17 CUDA_STANDARD_REQUIRED ON)
  target_include_directories(psim_cuda_objects PRIVATE ${PROJECT_SOURCE_DIR}/include
                                                       ${PROJECT_SOURCE_DIR}/src)
  target_compile_definitions(psim_cuda_objects PRIVATE PSIM_HAVE_CUDA _GNU_SOURCE)
  target_compile_definitions(${c_objects} PRIVATE PSIM_HAVE_CUDA)
  target_include_directories(${c_objects} PRIVATE ${CUDAToolkit_INCLUDE_DIRS})
endfunction()

# The CUDA objects and runtime into the libraries, the runtime static
# (libcudart_static.a: the programs that use psim need no CUDA library but
# the driver's): libpsim.so holds it; libpsim.a asks its consumers for
# it, at the path it was built with.
function(psim_cuda_link static shared)
  foreach(lib ${static} ${shared})
    target_sources(${lib} PRIVATE $<TARGET_OBJECTS:psim_cuda_objects>)
  endforeach()
  target_link_libraries(${shared} PRIVATE CUDA::cudart_static)
  # (and the C++ runtime nvcc's objects call: static locals' guards,
  # exceptions)
  target_link_libraries(${shared} PRIVATE stdc++)
  target_link_libraries(${static} PUBLIC $<BUILD_INTERFACE:CUDA::cudart_static>
                                         $<INSTALL_INTERFACE:${CUDA_cudart_static_LIBRARY}>
                                         $<INSTALL_INTERFACE:rt> stdc++)
  # psim.pc's Libs.private (cmake/install.cmake)
  set(PSIM_CUDA_PC_LIBS ${CUDA_cudart_static_LIBRARY} -lrt -lstdc++ PARENT_SCOPE)
endfunction()
