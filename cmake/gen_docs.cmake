# gen_docs.cmake — run at build time (cmake -P) with -DBVOX=<the bvox command>
# -DOUT=<folder>: writes OUT/man1/bvox.1, OUT/man1/bvox-<cmd>.1 per subcommand
# and OUT/bvox.bash, all printed by the command from its own command tables,
# so the manual and the completion never drift from the parser.
#
# HOOK: `bvox help --man [CMD]` and `bvox help --bash-completion` arrive with
# the table-driven CLI (branch cli-tables); the subcommands are the
# "Commands:" list of `bvox --help`. A command without them makes this script
# generate nothing (install then skips the files) instead of failing.
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
# the subcommands: the "Commands:" list of `bvox --help` (two spaces, a name)
execute_process(COMMAND ${BVOX} --help RESULT_VARIABLE rc OUTPUT_VARIABLE usage)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "bvox --help failed")
endif()
string(REGEX MATCH "\nCommands:\n(  [^\n]*\n)+" block "${usage}")
string(REGEX MATCHALL "\n  [a-z][a-z0-9-]*" cmds "${block}")
foreach(cmd IN LISTS cmds)
  string(STRIP "${cmd}" cmd)
  execute_process(COMMAND ${BVOX} help --man ${cmd} RESULT_VARIABLE rc OUTPUT_VARIABLE page)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "bvox help --man ${cmd} failed")
  endif()
  file(WRITE ${OUT}/man1/bvox-${cmd}.1 "${page}")
endforeach()
execute_process(COMMAND ${BVOX} help --bash-completion RESULT_VARIABLE rc OUTPUT_VARIABLE comp)
if(rc EQUAL 0)
  file(WRITE ${OUT}/bvox.bash "${comp}")
endif()
file(WRITE ${OUT}/stamp "done\n")
