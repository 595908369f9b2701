# BVOX_SANITIZE: ASan + UBSan for everything built in this tree, any error fatal.
if(BVOX_SANITIZE)
  set(BVOX_SAN_FLAGS -fsanitize=address,undefined,float-cast-overflow -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_compile_options(${BVOX_SAN_FLAGS} -O1 -g)
  add_link_options(${BVOX_SAN_FLAGS})
endif()
