# CMake generated Testfile for 
# Source directory: /work/main/tests
# Build directory: /work/main/tests
# 
# This file includes the relevant testing commands required for 
# testing this directory and lists subdirectories to be tested as well.
add_test(scenes_io "/work/main/tests/test_scenes_io")
set_tests_properties(scenes_io PROPERTIES  ENVIRONMENT "LT_TEST_DATA=/work/main/tests" TIMEOUT "900" _BACKTRACE_TRIPLES "/work/main/tests/CMakeLists.txt;9;add_test;/work/main/tests/CMakeLists.txt;0;")
add_test(cli "bash" "/work/main/tests/cli_errors.sh" "/work/main/lazytrace")
set_tests_properties(cli PROPERTIES  TIMEOUT "600" _BACKTRACE_TRIPLES "/work/main/tests/CMakeLists.txt;15;add_test;/work/main/tests/CMakeLists.txt;0;")
