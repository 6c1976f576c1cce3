# The quick tier (`make test`, label quick; issue 48 item 19, docs/reliability.md). Besides
# vpcontact_quick_tests (tests/CMakeLists.txt): the program's paper-1d run with its figures (VTU files read back),
# `check` of the paper's 2D case and of the Gmsh-meshed dome (Gmsh's child process), two refused
# options, the module graph and the Makefile's targets; tests/mpi/ adds one MPI run and python/ the
# module's tests.
# What `make test` builds: what the quick tests run (and no other test executable).
add_custom_target(vpcontact_quick_tier)
add_dependencies(vpcontact_quick_tier vpcontact vpcontact_quick_tests)
if(TARGET vpcontact_python)
  add_dependencies(vpcontact_quick_tier vpcontact_python)
endif()
# `make test` builds that target alone and runs the quick tier; every module is in it.
add_test(NAME build.make_test_builds_the_quick_tier
         COMMAND bash -c "make -n -C \"$0\" test BUILD=/nonexistent/build > \"$1\" && \
                          grep -E -- '--build /nonexistent/build .*--target vpcontact_quick_tier$' \"$1\" && \
                          grep -E -- 'ctest .* -L quick$' \"$1\""
                 ${PROJECT_SOURCE_DIR} ${CMAKE_CURRENT_BINARY_DIR}/make_test.txt)
set_tests_properties(build.make_test_builds_the_quick_tier PROPERTIES LABELS build)
add_test(NAME build.quick_tier_touches_every_module
         COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/quick_tier.sh ${CMAKE_CTEST_COMMAND} ${CMAKE_BINARY_DIR}
                 ${VPCONTACT_PYTHON} ${VPCONTACT_ENABLE_PETSC})
set_tests_properties(build.quick_tier_touches_every_module PROPERTIES LABELS build
                     PASS_REGULAR_EXPRESSION "every module touched")
vpc_quick(cli.run_paper_1d cli.run_plot cli.check_paper-2d cli.check_dome-3d cli.negative_step cli.unknown_case
          scripts.module_graph build.make_run_builds_the_program_alone build.make_test_builds_the_quick_tier
          build.quick_tier_touches_every_module)
