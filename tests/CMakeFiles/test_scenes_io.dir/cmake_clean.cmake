file(REMOVE_RECURSE
  "CMakeFiles/test_scenes_io.dir/support.c.o"
  "CMakeFiles/test_scenes_io.dir/support.c.o.d"
  "CMakeFiles/test_scenes_io.dir/test_scenes_io.c.o"
  "CMakeFiles/test_scenes_io.dir/test_scenes_io.c.o.d"
  "test_scenes_io"
  "test_scenes_io.pdb"
)

# Per-language clean rules from dependency scanning.
foreach(lang C)
  include(CMakeFiles/test_scenes_io.dir/cmake_clean_${lang}.cmake OPTIONAL)
endforeach()
