# BVOX_SANITIZE: ASan + UBSan for everything built in this tree, any error fatal.
if(BVOX_SANITIZE)
  set(BVOX_SAN_FLAGS -fsanitize=address,undefined,float-cast-overflow -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_compile_options(${BVOX_SAN_FLAGS} -O1 -g)
  add_link_options(${BVOX_SAN_FLAGS})
endif()

# BVOX_TSAN: ThreadSanitizer (not with BVOX_SANITIZE: the two cannot be
# combined). scripts/test.sh builds only the thread stress test with it.
if(BVOX_TSAN)
  if(BVOX_SANITIZE)
    message(FATAL_ERROR "BVOX_TSAN and BVOX_SANITIZE cannot be combined")
  endif()
  set(BVOX_TSAN_FLAGS -fsanitize=thread -fno-omit-frame-pointer)
  add_compile_options(${BVOX_TSAN_FLAGS} -O1 -g)
  add_link_options(${BVOX_TSAN_FLAGS})
endif()
