# The SIMD kernels are compiled with their instruction set enabled, each in its
# own file; the rest of the library stays portable (no -march=native) and
# src/core/simd/dispatch.c picks a path at run time from the CPU's features.
function(bvox_simd_sources target)
  if(CMAKE_SYSTEM_PROCESSOR MATCHES "x86_64|AMD64|amd64")
    set_source_files_properties(${CMAKE_CURRENT_SOURCE_DIR}/src/core/simd/kernels_avx2.c
      PROPERTIES COMPILE_OPTIONS "-mavx2;-mpopcnt")
    set_source_files_properties(${CMAKE_CURRENT_SOURCE_DIR}/src/core/simd/kernels_avx512.c
      PROPERTIES COMPILE_OPTIONS "-mavx512f;-mavx512vpopcntdq;-mavx2;-mpopcnt")
    file(GLOB avx2_extra ${CMAKE_CURRENT_SOURCE_DIR}/src/*/*_avx2.c)
    file(GLOB avx512_extra ${CMAKE_CURRENT_SOURCE_DIR}/src/*/*_avx512.c)
    foreach(f IN LISTS avx2_extra)
      set_source_files_properties(${f} PROPERTIES COMPILE_OPTIONS "-mavx2;-mbmi2;-mpopcnt")
    endforeach()
    foreach(f IN LISTS avx512_extra)
      set_source_files_properties(${f} PROPERTIES COMPILE_OPTIONS
        "-mavx512f;-mavx512bw;-mavx512vl;-mavx512vpopcntdq;-mavx2;-mbmi2;-mpopcnt")
    endforeach()
  endif()
endfunction()
