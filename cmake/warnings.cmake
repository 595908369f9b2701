# Warnings for our own targets (not for dependencies).
function(bvox_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wshadow -Wstrict-prototypes
                                           -Wno-unused-parameter -Werror=implicit-function-declaration)
endfunction()
