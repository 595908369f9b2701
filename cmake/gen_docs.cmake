# gen_docs.cmake — run at build time (cmake -P) with -DBVOX=<the bvox command>
# -DOUT=<folder>: writes OUT/man1/bvox.1, OUT/man1/bvox-<cmd>.1 per subcommand
# and OUT/bvox.bash, all printed by the command from its own command tables,
# so the manual and the completion never drift from the parser.
#
# HOOK: `bvox help --man [CMD]`, `bvox help --bash-completion` and
# `bvox help --commands` (one subcommand name per line) arrive with the
# table-driven CLI (branch cli-tables). A command without them makes this
# script generate nothing (install then skips the files) instead of failing.
file(REMOVE_RECURSE ${OUT}/man1)
file(REMOVE ${OUT}/bvox.bash)
file(MAKE_DIRECTORY ${OUT})
execute_process(COMMAND ${BVOX} help --man RESULT_VARIABLE rc OUTPUT_VARIABLE page ERROR_QUIET)
if(NOT rc EQUAL 0)
  message(STATUS "bvox has no `help --man` yet (cli-tables): no manual pages or completion generated")
  file(WRITE ${OUT}/stamp "skipped\n")
  return()
endif()
file(MAKE_DIRECTORY ${OUT}/man1)
file(WRITE ${OUT}/man1/bvox.1 "${page}")
execute_process(COMMAND ${BVOX} help --commands RESULT_VARIABLE rc OUTPUT_VARIABLE cmds ERROR_QUIET)
if(rc EQUAL 0)
  string(REGEX REPLACE "\n$" "" cmds "${cmds}")
  string(REPLACE "\n" ";" cmds "${cmds}")
  foreach(cmd IN LISTS cmds)
    execute_process(COMMAND ${BVOX} help --man ${cmd} RESULT_VARIABLE rc OUTPUT_VARIABLE page)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "bvox help --man ${cmd} failed")
    endif()
    file(WRITE ${OUT}/man1/bvox-${cmd}.1 "${page}")
  endforeach()
endif()
execute_process(COMMAND ${BVOX} help --bash-completion RESULT_VARIABLE rc OUTPUT_VARIABLE comp)
if(rc EQUAL 0)
  file(WRITE ${OUT}/bvox.bash "${comp}")
endif()
file(WRITE ${OUT}/stamp "done\n")
