# Hostile input, full disks and concurrent runs (the promises in docs/reliability.md).
# Included at the end of tests/CMakeLists.txt: EXPECT_ERROR, SPLATS_CUBE and PRESENT_CACHE are set.
set(HOSTILE_DIR ${CMAKE_CURRENT_BINARY_DIR}/hostile)
file(MAKE_DIRECTORY ${HOSTILE_DIR})

# Outputs: every image writer on a full disk, batch outputs that would replace inputs, an unwritable
# output directory, two batch runs at once, a killed csm build's temporary (tests/cli/hostile_outputs_test.sh).
foreach(mode full-disk-coherence full-disk-coherence-build full-disk-splats-render full-disk-cluster full-disk-render
             batch-summary-is-manifest batch-summary-is-output batch-summary-is-lock batch-input-is-lock batch-summary-folder-missing batch-output-in-output batch-fifo-input batch-output-is-input batch-output-inside-input
             batch-output-contains-input batch-unwritable batch-concurrent batch-concurrent-summary batch-same-shard-twice batch-scan-own-folders
             threads-follow-affinity csm-leftover sigterm-csm-build sigterm-batch sigterm-cluster render-cache-read-only)
  add_test(NAME hostile.${mode} COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cli/hostile_outputs_test.sh ${mode} $<TARGET_FILE:splatcl>
           ${HOSTILE_DIR}/${mode} ${EXPECT_ERROR})
  set_tests_properties(hostile.${mode} PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 120)
endforeach()
set_tests_properties(hostile.full-disk-render PROPERTIES FIXTURES_REQUIRED present_cache ${GL_TEST_PROPERTIES})
set_tests_properties(hostile.render-cache-read-only PROPERTIES TIMEOUT 120 ${GL_TEST_PROPERTIES})

# Stated limits: one line before anything is allocated (each ran for a minute into std::bad_alloc).
function(hostile_error name pattern)
  add_test(NAME hostile.${name} COMMAND ${EXPECT_ERROR} "${pattern}" $<TARGET_FILE:splatcl> ${ARGN})
  set_tests_properties(hostile.${name} PROPERTIES TIMEOUT 20)
endfunction()
# A directory whose file system makes no files (/proc, as root): the cause was "No such file or
# directory". Another user is refused by its permissions.
hostile_error(output_in_proc "cannot write -o /proc/x.csm: directory /proc is not writable \\((its file system does not take new files|Permission denied)\\)$"
              csm build ${SPLATS_CUBE} -o /proc/x.csm)
hostile_error(limit_cluster_lights "--lights 1000000000 is not a light count in \\[0, 1048576\\]$" cluster --lights 1000000000)
hostile_error(limit_cluster_lights_negative "--lights -1 is not a light count" cluster --lights -1)
hostile_error(limit_cluster_size "--size '100000x100000' is not WIDTHxHEIGHT with sides in 1..16384$" cluster --size 100000x100000)
hostile_error(limit_cluster_size_negative "--size '-5x5' is not WIDTHxHEIGHT with sides in 1..16384$" cluster --size -5x5)
hostile_error(limit_cluster_pixels "--size '16384x16384' has 268435456 pixels, more than the limit of 33554432$" cluster --size 16384x16384)
file(WRITE ${HOSTILE_DIR}/billion-lights.json "{\"objects\": [], \"lights\": {\"count\": 1000000000}}")
hostile_error(limit_scene_lights "billion-lights.json: lights: 'count' must be an integer in \\[0, 1048576\\]$"
              cluster ${HOSTILE_DIR}/billion-lights.json)
hostile_error(limit_render_lights "--lights -5 is not a light count in \\[0, 1048576\\]$" render --lights -5)
# The limit holds for listed and generated lights together (2 listed and 2^20 generated were taken).
file(WRITE ${HOSTILE_DIR}/two-lights.json "{\"objects\": [], \"lights\": [{\"position\": [0, 1, 0], \"radius\": 1}, {\"position\": [1, 1, 0], \"radius\": 1}]}")
hostile_error(limit_listed_and_generated_lights "1048576 generated lights and the scene's 2 listed ones make 1048578, more than the limit of 1048576 lights$"
              cluster ${HOSTILE_DIR}/two-lights.json --lights 1048576)
hostile_error(limit_ao_samples "ao: --samples 100000000 is not a direction count in 1..4096$"
              ao ${SPLATS_CUBE} --occluder missing.csm -o ${HOSTILE_DIR}/ao.ply --samples 100000000)
hostile_error(limit_quality_image "--image 100000 is not an image side in 1..4096$" csm quality ${SPLATS_CUBE} --image 100000)

# Option values that were ignored or accepted: negative, NaN, empty, out of range, unknown words.
hostile_error(option_render_lod_nan "--lod nan is not a pixel error in \\[0, 1000\\]$" render --lod nan)
hostile_error(option_render_dt_nan "--dt nan is not a time step in seconds" render --dt nan)
# (through sh: CMake drops an empty argument)
add_test(NAME hostile.option_empty_device COMMAND ${EXPECT_ERROR} "--device: empty: give an index, a type \\(cpu, gpu, simulator\\) or a name substring"
         sh -c "\"$<TARGET_FILE:splatcl>\" devices --device ''")
hostile_error(option_pixel_order "unknown pixel order 'x'" csm build ${SPLATS_CUBE} -o ${HOSTILE_DIR}/x.csm --pixel-order x)
# Options that another option makes meaningless were ignored silently (a helper's audit).
hostile_error(option_pixel_order_per_pixel "csm build: --pixel-order is the pixel curve of --mode per-map; --mode per-pixel has none$"
              csm build ${SPLATS_CUBE} -o ${HOSTILE_DIR}/x.csm --pixel-order zigzag-v)
hostile_error(option_coherence_per_map "csm build: --mode per-map only measures sizes; --coherence maps per-pixel CSMs only$"
              csm build ${SPLATS_CUBE} --mode per-map --coherence ${HOSTILE_DIR}/coherence.png)
hostile_error(option_verify_capture_without_model "csm verify: --capture is for the recapture, which needs the MODEL the file was built from$"
              csm verify ${CSM_OUT} --capture raycast)
hostile_error(option_verify_bad_capture "unknown capture method 'foo'" csm verify ${CSM_OUT} ${SPLATS_CUBE} --capture foo)
hostile_error(option_quality_light_max_huge "--light-max 1e\\+30 is not a light distance in \\(1.05, 1e6\\] sphere radii$"
              csm quality ${SPLATS_CUBE} --light-max 1e30)
file(WRITE ${HOSTILE_DIR}/five-key-lights.json "{\"objects\": [], \"key_lights\": [{\"position\": [0, 3, 0]}, {\"position\": [1, 3, 0]}, {\"position\": [2, 3, 0]}, {\"position\": [3, 3, 0]}, {\"position\": [4, 3, 0]}]}")
hostile_error(limit_cluster_key_lights "five-key-lights.json: 'key_lights' lists 5 lights, at most 4$" cluster ${HOSTILE_DIR}/five-key-lights.json --size 64x48)
foreach(fov 0 360 -5)
  hostile_error(option_quality_fov_${fov} "--fov ${fov} is not a field of view in \\(0, 180\\) degrees$" csm quality ${SPLATS_CUBE} --fov ${fov})
endforeach()
# A negative bias shadowed every receiver by its own surface (a helper's audit).
foreach(bias nan -1)
  hostile_error(option_quality_bias_${bias} "--bias ${bias} is not a texel count in 0..1000$" csm quality ${SPLATS_CUBE} --bias ${bias})
  hostile_error(option_ao_bias_${bias} "ao: --bias ${bias} is not a texel count in 0..1000$" ao ${SPLATS_CUBE} --occluder ${CSM_OUT} --bias ${bias} -o x.ply)
endforeach()
hostile_error(option_ao_lift_negative "ao: --lift -1 is not a texel count in 0..1000$" ao ${SPLATS_CUBE} --occluder ${CSM_OUT} --lift -1 -o x.ply)
foreach(distance 0.5 nan 5000000)
  hostile_error(option_quality_camera_${distance} "--camera-distance ${distance} is not a distance in 1..1e6 sphere radii$"
                csm quality ${SPLATS_CUBE} --camera-distance ${distance})
endforeach()
hostile_error(option_unconvertible "^splatcl: --samples -5: not a whole number 1 or more \\(see --help\\)$" ao ${SPLATS_CUBE} --samples -5)
hostile_error(option_too_large "^splatcl: --frames 99999999999: too large \\(see --help\\)$" render --frames 99999999999)
hostile_error(option_unknown_subcommand "unknown csm command 'frobnicate' \\(known: build, info, verify, quality, analyze\\)$" csm frobnicate)

# Unknown keys in scenes: a typo is an error naming the file and the key, not a silent default.
file(WRITE ${HOSTILE_DIR}/cluster-typo.json
     "{\"objects\": [], \"lights\": [{\"position\": [0, 1, 0], \"radius\": 2, \"colour\": [1, 0, 0]}]}")
hostile_error(scene_cluster_unknown_key "cluster-typo.json: 'colour' is not a key of lights\\[0\\] \\(known: position, radius, color, size\\)$"
              cluster ${HOSTILE_DIR}/cluster-typo.json)
file(WRITE ${HOSTILE_DIR}/present-typo.json "{\"objects\": [{\"mesh\": {\"procedural\": \"box\"}, \"positon\": [0, 1, 0]}]}")
hostile_error(scene_present_unknown_key "present-typo.json: 'positon' is not a key of objects\\[0\\] \\(known: name, mesh, color, "
              render ${HOSTILE_DIR}/present-typo.json)
file(WRITE ${HOSTILE_DIR}/present-quality-typo.json "{\"objects\": [], \"quality\": {\"shadow\": \"off\"}}")
hostile_error(scene_present_unknown_quality_key "present-quality-typo.json: 'shadow' is not a key of quality"
              render ${HOSTILE_DIR}/present-quality-typo.json)

# Messages naming the real cause: a directory is a directory, not "no such file" or bad JSON.
hostile_error(message_cluster_scene_directory "cannot read scene ${HOSTILE_DIR}: it is a directory$" cluster ${HOSTILE_DIR})
hostile_error(message_render_scene_directory "cannot read scene ${HOSTILE_DIR}: it is a directory$" render ${HOSTILE_DIR})

# Faces dropped while reading (an index out of range) are one warning line in every command, not silent.
file(WRITE ${HOSTILE_DIR}/bad-index.obj "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 1 2 99\n")
add_test(NAME hostile.mesh_warning_csm_build COMMAND splatcl csm build ${HOSTILE_DIR}/bad-index.obj -o ${HOSTILE_DIR}/bad-index.csm
         --maps 16 --res 8 --reference)
set_tests_properties(hostile.mesh_warning_csm_build PROPERTIES
                     PASS_REGULAR_EXPRESSION "splatcl: warning: [^\n]*bad-index.obj: 1 face with an index out of range or unreadable dropped")

# Splat PLY headers and records, .csm pole frames and object transforms (item 6): crafted files with
# a valid checksum (tests/cli/make_hostile_files.cpp) and header bit flips are refused with one line
# naming the file and the fault.
add_executable(splatcl_make_hostile_files ${CMAKE_CURRENT_SOURCE_DIR}/cli/make_hostile_files.cpp)
target_include_directories(splatcl_make_hostile_files PRIVATE ${PROJECT_SOURCE_DIR}/host)
target_link_libraries(splatcl_make_hostile_files PRIVATE splatcl_csm splatcl_splats)
add_test(NAME hostile.csm_good COMMAND splatcl csm build ${SPLATS_CUBE} -o ${HOSTILE_DIR}/hostile-good.csm --maps 16 --res 8 --reference)
set_tests_properties(hostile.csm_good PROPERTIES FIXTURES_SETUP hostile_csm)
add_test(NAME hostile.make_files COMMAND splatcl_make_hostile_files ${HOSTILE_DIR} ${HOSTILE_DIR}/hostile-good.csm)
set_tests_properties(hostile.make_files PROPERTIES FIXTURES_SETUP hostile_splats FIXTURES_REQUIRED hostile_csm)
set(HOSTILE_PLANE ${HOSTILE_DIR}/verify-plane.obj)
file(WRITE ${HOSTILE_PLANE} "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n")
add_test(NAME hostile.splats_good COMMAND splatcl splats verify ${HOSTILE_PLANE} ${HOSTILE_DIR}/hostile-good.ply --points 1000)
set_tests_properties(hostile.splats_good PROPERTIES FIXTURES_REQUIRED hostile_splats)
set(properties_message "the properties are not those of a splat file")
foreach(case "double-x|${properties_message}" "swapped-xy|${properties_message}" "floqt|${properties_message}"
             "negative-k|k -3 is not in 1..1024" "nan-normal|splat 0: the normal is not a finite unit vector"
             "nan-axis|splat 0: non-finite semi-axis" "negative-axis|splat 0: major axis length -0.4 is not the length 0.145 of its vector"
             "eps-flip|checksum mismatch \\(corrupted header or body\\)")
  string(REPLACE "|" ";" parts "${case}")
  list(GET parts 0 name)
  list(GET parts 1 pattern)
  hostile_error(splats_${name} "splat file .*hostile-${name}.ply: ${pattern}" splats verify ${HOSTILE_PLANE} ${HOSTILE_DIR}/hostile-${name}.ply)
  set_tests_properties(hostile.splats_${name} PROPERTIES FIXTURES_REQUIRED hostile_splats)
endforeach()
foreach(case "zero-pole-frame|the pole frame does not match pole axis y" "nan-pole-frame|the pole frame does not match pole axis y"
             "singular-transform|the object transform is singular \\(determinant 0\\)"
             "projective-transform|the object transform is not affine"
             "odd-map-count|its 257 maps do not fit the uniform distribution's grid$")
  string(REPLACE "|" ";" parts "${case}")
  list(GET parts 0 name)
  list(GET parts 1 pattern)
  hostile_error(csm_${name} "hostile-${name}.csm: ${pattern}" csm verify ${HOSTILE_DIR}/hostile-${name}.csm)
  set_tests_properties(hostile.csm_${name} PROPERTIES FIXTURES_REQUIRED hostile_splats)
endforeach()

# Batch manifests: a JSON boolean spelled as a string is refused; a CSV with a UTF-8 byte order mark reads.
file(WRITE ${HOSTILE_DIR}/clip-yes.json "{\"models\": [{\"path\": \"${SPLATS_CUBE}\", \"clip\": \"yes\"}]}")
hostile_error(manifest_json_boolean_string "clip-yes.json: models\\[0\\] \\(splats-cube\\): 'clip' must be true or false, got 'yes'$"
              batch ${HOSTILE_DIR}/clip-yes.json -o ${HOSTILE_DIR}/clip-yes-out)
string(ASCII 239 187 191 utf8_bom)
file(WRITE ${HOSTILE_DIR}/bom.csv "${utf8_bom}path\n${SPLATS_CUBE}\n")
add_test(NAME hostile.manifest_csv_bom COMMAND splatcl batch ${HOSTILE_DIR}/bom.csv --list)
set_tests_properties(hostile.manifest_csv_bom PROPERTIES PASS_REGULAR_EXPRESSION "^splats-cube\t")

# Scene problems are worded as the scene's, naming its file, not as a command-line flag.
file(WRITE ${HOSTILE_DIR}/present-maps.json "{\"objects\": [{\"mesh\": {\"procedural\": \"box\"}}], \"quality\": {\"csm_maps\": 1000}}")
hostile_error(message_scene_csm_maps "present-maps.json: 'csm_maps' 1000 is not a perfect square" render ${HOSTILE_DIR}/present-maps.json)
# Batch: mesh problems are reported per model (the log line and the summary), not silent.
file(WRITE ${HOSTILE_DIR}/bad-index.csv "path\n${HOSTILE_DIR}/bad-index.obj\n")
# A fresh output directory: a rerun reuses the model ("reused"), and the pattern wants a build.
add_test(NAME hostile.mesh_warning_batch COMMAND sh -c "rm -rf \"$1\" && \"$0\" batch \"$2\" -o \"$1\" --reference --outputs csm --maps 16 --res 8"
         $<TARGET_FILE:splatcl> ${HOSTILE_DIR}/bad-index-out ${HOSTILE_DIR}/bad-index.csv)
set_tests_properties(hostile.mesh_warning_batch PROPERTIES
                     PASS_REGULAR_EXPRESSION "ok      bad-index \\(csm [^\n]*\\); warning: 1 face with an index out of range or unreadable dropped")
file(MAKE_DIRECTORY ${HOSTILE_DIR}/dir.json ${HOSTILE_DIR}/dir.csm ${HOSTILE_DIR}/dir.obj)
hostile_error(message_bench_results_directory "cannot read ${HOSTILE_DIR}/dir.json: it is a directory$" bench report ${HOSTILE_DIR}/dir.json)
hostile_error(message_csm_directory "cannot read ${HOSTILE_DIR}/dir.csm: it is a directory$" csm info ${HOSTILE_DIR}/dir.csm)
hostile_error(message_mesh_directory "cannot read mesh ${HOSTILE_DIR}/dir.obj: it is a directory$" csm build ${HOSTILE_DIR}/dir.obj -o ${HOSTILE_DIR}/x.csm)
# A crafted map count is refused by the checksum before the grid is sized (it allocated gigabytes
# first): under a 1 GiB address-space limit the answer is still the checksum, not "out of memory".
# AddressSanitizer reserves terabytes of shadow address space, so under it its own allocation cap
# (1 GiB, failing allocations return null: std::bad_alloc) stands in for the ulimit.
# The same count resealed (a valid checksum) is refused by the map-count limit before the grid is
# sized (it went on to allocate the grid's tables: std::bad_alloc under the limit).
foreach(case "huge-map-count|checksum mismatch \\(the file is corrupted\\)"
             "resealed-huge-map-count|its map count 2147395600 is not in 1..16777216")
  string(REPLACE "|" ";" parts "${case}")
  list(GET parts 0 name)
  list(GET parts 1 pattern)
  set(args ${EXPECT_ERROR} "hostile-${name}.csm: ${pattern}$" $<TARGET_FILE:splatcl> csm info ${HOSTILE_DIR}/hostile-${name}.csm)
  if(SPLATCL_SANITIZE)
    add_test(NAME hostile.csm_${name} COMMAND ${args})
    set_tests_properties(hostile.csm_${name} PROPERTIES ENVIRONMENT_MODIFICATION
                         "ASAN_OPTIONS=string_append::max_allocation_size_mb=1024:allocator_may_return_null=1")
  else()
    add_test(NAME hostile.csm_${name} COMMAND sh -c "ulimit -v 1048576 && exec \"$0\" \"$@\"" ${args})
  endif()
  set_tests_properties(hostile.csm_${name} PROPERTIES FIXTURES_REQUIRED hostile_splats TIMEOUT 20)
endforeach()
add_test(NAME hostile.csm_info_transform COMMAND splatcl csm info ${HOSTILE_DIR}/hostile-good.csm)
set_tests_properties(hostile.csm_info_transform PROPERTIES FIXTURES_REQUIRED hostile_csm PASS_REGULAR_EXPRESSION "transform  identity \\(the model as loaded\\)")
# csm verify moves the model by the stored object transform before it recaptures (it ignored it):
# the CSM of the unit cube stored with "model x + 1 = object x" verifies against the cube shifted by
# -1 in x, and not against the unshifted cube.
file(WRITE ${HOSTILE_DIR}/cube-shifted.obj "v -1 0 0\nv 0 0 0\nv 0 1 0\nv -1 1 0\nv -1 0 1\nv 0 0 1\nv 0 1 1\nv -1 1 1\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 3 4 8 7\nf 2 3 7 6\nf 1 5 8 4\n")
add_test(NAME hostile.csm_verify_transform COMMAND splatcl csm verify ${HOSTILE_DIR}/hostile-translated.csm ${HOSTILE_DIR}/cube-shifted.obj --reference)
set_tests_properties(hostile.csm_verify_transform PROPERTIES FIXTURES_REQUIRED hostile_splats PASS_REGULAR_EXPRESSION "lossless   all ")
hostile_error(csm_verify_transform_unshifted "the CSM was not built from .*splats-cube.obj: its bounding sphere" csm verify ${HOSTILE_DIR}/hostile-translated.csm ${SPLATS_CUBE} --reference)
set_tests_properties(hostile.csm_verify_transform_unshifted PROPERTIES FIXTURES_REQUIRED hostile_splats)
# Batch manifests: a JSON number spelled as a string is refused like a boolean spelled as one.
file(WRITE ${HOSTILE_DIR}/k-string.json "{\"models\": [{\"path\": \"${SPLATS_CUBE}\", \"k\": \"10\"}]}")
hostile_error(manifest_json_number_string "k-string.json: models\\[0\\] \\(splats-cube\\): 'k' must be a number, got '10'$"
              batch ${HOSTILE_DIR}/k-string.json -o ${HOSTILE_DIR}/k-string-out)
# A far plane beyond float range was read as inf and refused without naming the scene or the field.
file(WRITE ${HOSTILE_DIR}/far-beyond-float.json "{\"objects\": [{\"name\": \"s\", \"mesh\": {\"procedural\": \"sphere\"}}], \"camera\": {\"eye\": [0, 0, 5], \"target\": [0, 0, 0], \"far\": 1e39}}")
hostile_error(scene_far_beyond_float "far-beyond-float.json: camera.far is beyond float range" cluster ${HOSTILE_DIR}/far-beyond-float.json --size 16x16)
# Empty values: bench took --device '' as the default device (devices and cluster refused it), and
# cluster -o '' wrote nothing and exited 0.
# (add_test itself: a function's ARGN drops empty arguments)
add_test(NAME hostile.option_bench_device_empty COMMAND ${EXPECT_ERROR} "--device: empty: give an index" $<TARGET_FILE:splatcl> bench --quick --device "")
add_test(NAME hostile.option_bench_tune_device_empty COMMAND ${EXPECT_ERROR} "--device: empty: give an index" $<TARGET_FILE:splatcl> bench tune --device ""
         -o ${HOSTILE_DIR}/tune.json)
add_test(NAME hostile.option_cluster_output_empty COMMAND ${EXPECT_ERROR} "--output: empty: name a directory" $<TARGET_FILE:splatcl> cluster -o "" --size 8x8)
# --quick replaced a given --size silently (and capped a given --runs at 2).
hostile_error(option_bench_quick_with_size "--quick sets its own problem sizes: drop --size or --quick$" bench primitives --quick --size 1000)
hostile_error(option_bench_quick_with_size_on_bench "--quick sets its own problem sizes" bench --size 1000 primitives --quick)
hostile_error(option_bench_tune_quick_with_size "--quick sets its own problem sizes" bench tune --quick --size 1000 -o ${HOSTILE_DIR}/tune-quick.json)
add_test(NAME hostile.option_bench_quick_keeps_given_runs COMMAND ${EXPECT_OUTPUT} --file ${HOSTILE_DIR}/quick-runs.json "\"runs\": 3"
         -- $<TARGET_FILE:splatcl> bench primitives --quick --runs 3 --device cpu --json ${HOSTILE_DIR}/quick-runs.json)
# A mesh far from the origin for its size loses its detail on reading (vertices are floats): a unit
# tetrahedron at 1e7 built a CSM without a word. Near the origin the same mesh warns of nothing.
file(WRITE ${HOSTILE_DIR}/tetra-1e7.obj "v 10000000 0 0\nv 10000001 0 0\nv 10000000 1 0\nv 10000000 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
file(WRITE ${HOSTILE_DIR}/tetra-near.obj "v 1000 0 0\nv 1001 0 0\nv 1000 1 0\nv 1000 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
add_test(NAME hostile.mesh_far_from_origin_warns COMMAND ${EXPECT_OUTPUT}
         --match "tetra-1e7.obj: coordinates reach 1e\\+07, where floats step by 1 \\(58 % of the mesh's 1.732 diagonal\\): detail finer than that was lost on reading"
         -- $<TARGET_FILE:splatcl> csm build ${HOSTILE_DIR}/tetra-1e7.obj -o ${HOSTILE_DIR}/tetra-1e7.csm --maps 16 --res 8)
add_test(NAME hostile.mesh_near_origin_does_not_warn COMMAND ${EXPECT_OUTPUT} --no-match "warning"
         -- $<TARGET_FILE:splatcl> csm build ${HOSTILE_DIR}/tetra-near.obj -o ${HOSTILE_DIR}/tetra-near.csm --maps 16 --res 8)
# A tenth-of-a-millimetre tetrahedron at 1e6 reads as one point: csm build and splats said only
# "zero extent" or "eps resolves to 0", and ao took it as a receiver of AO 1 with no float warning.
file(WRITE ${HOSTILE_DIR}/tetra-collapsed.obj "v 1000000 1000000 1000000\nv 1000000.0001 1000000 1000000\nv 1000000 1000000.0001 1000000\nv 1000000 1000000 1000000.0001\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
set(COLLAPSED_CAUSE "tetra-collapsed.obj: the mesh has zero extent: coordinates reach 1000000, where floats step by 0.0625: every vertex reads as the same point")
hostile_error(mesh_collapsed_csm "${COLLAPSED_CAUSE}" csm build ${HOSTILE_DIR}/tetra-collapsed.obj -o ${HOSTILE_DIR}/tetra-collapsed.csm --maps 16 --res 8)
# splats reads it about the centre of its box in double (the splat file records that origin), so
# it keeps its shape: built, with a warning saying where its positions are relative to.
add_test(NAME hostile.mesh_collapsed_splats_about_its_centre COMMAND ${EXPECT_OUTPUT}
         --match "warning: .*tetra-collapsed.obj: coordinates reach 1000000, where floats step by 0.0625 .*: read about the centre of its bounding box \\(1000000\\.0000[0-9]*, 1000000\\.0000[0-9]*, 1000000\\.0000[0-9]*\\) instead"
         -- $<TARGET_FILE:splatcl> splats ${HOSTILE_DIR}/tetra-collapsed.obj -o ${HOSTILE_DIR}/tetra-collapsed.ply)
add_test(NAME hostile.mesh_collapsed_splats_verify COMMAND ${EXPECT_OUTPUT} --match "^ok$"
         -- $<TARGET_FILE:splatcl> splats verify ${HOSTILE_DIR}/tetra-collapsed.obj ${HOSTILE_DIR}/tetra-collapsed.ply)
set_tests_properties(hostile.mesh_collapsed_splats_verify PROPERTIES DEPENDS hostile.mesh_collapsed_splats_about_its_centre)
# Checked against the same part moved to the origin by hand, verify names the mismatch of origins
# (it said "translate the mesh nearer the origin" of a mesh at the origin).
file(WRITE ${HOSTILE_DIR}/tetra-collapsed-moved.obj "v 0 0 0\nv 0.0001 0 0\nv 0 0.0001 0\nv 0 0 0.0001\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
hostile_error(mesh_verify_against_a_mesh_away_from_the_splats_origin
              "the splats' positions are relative to origin \\(1000000.00005, 1000000.00005, 1000000.00005\\) \\(their file's splatcl_origin\\), and this mesh's box is centred 1.73205e\\+06 from it, more than its 0.0001732 diagonal: is it the mesh they were built from\\?$"
              splats verify ${HOSTILE_DIR}/tetra-collapsed-moved.obj ${HOSTILE_DIR}/tetra-collapsed.ply)
set_tests_properties(hostile.mesh_verify_against_a_mesh_away_from_the_splats_origin PROPERTIES DEPENDS hostile.mesh_collapsed_splats_about_its_centre)
# The other way round: splats at origin 0 (of the part moved to the origin) against the part far out.
add_test(NAME hostile.mesh_moved_splats COMMAND ${EXPECT_OUTPUT} --no-match "warning"
         -- $<TARGET_FILE:splatcl> splats ${HOSTILE_DIR}/tetra-collapsed-moved.obj -o ${HOSTILE_DIR}/tetra-collapsed-moved.ply)
hostile_error(mesh_verify_origin_zero_against_a_far_mesh
              "the splat file records origin 0, but this mesh's coordinates are coarse as floats for its size"
              splats verify ${HOSTILE_DIR}/tetra-collapsed.obj ${HOSTILE_DIR}/tetra-collapsed-moved.ply)
set_tests_properties(hostile.mesh_verify_origin_zero_against_a_far_mesh PROPERTIES DEPENDS hostile.mesh_moved_splats)
# Not coarse for its size, but at a fine eps the float steps at 1000 would take more than a quarter
# of it (refused where they took half: "translate the mesh nearer the origin"): read about its centre.
add_test(NAME hostile.mesh_fine_eps_far_out_splats_about_its_centre COMMAND ${EXPECT_OUTPUT}
         --match "warning: .*tetra-near.obj: coordinates reach 1001, where floats step by 6.1e-05 .*: read about the centre of its bounding box \\(1000.5, 0.5, 0.5\\) instead"
         -- $<TARGET_FILE:splatcl> splats ${HOSTILE_DIR}/tetra-near.obj -o ${HOSTILE_DIR}/tetra-near-fine.ply --eps 0.0003)
add_test(NAME hostile.mesh_near_origin_splats_as_given COMMAND ${EXPECT_OUTPUT} --no-match "warning"
         -- $<TARGET_FILE:splatcl> splats ${HOSTILE_DIR}/tetra-near.obj -o ${HOSTILE_DIR}/tetra-near.ply)
# A closed plate thinner than the CSM's hit epsilon reads as solid to the bounding sphere's exit
# behind it: csm build warns with the share of rays that meet it once (nothing said so).
file(WRITE ${HOSTILE_DIR}/plate-thin.obj "v -50 -0.0005 -50\nv 50 -0.0005 -50\nv 50 0.0005 -50\nv -50 0.0005 -50\nv -50 -0.0005 50\nv 50 -0.0005 50\nv 50 0.0005 50\nv -50 0.0005 50\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n")
add_test(NAME hostile.csm_thin_closed_part_warns COMMAND ${EXPECT_OUTPUT}
         --match "warning: .*plate-thin.obj: [0-9]+ of [0-9]+ sample rays that hit this closed mesh \\(5[0-9][.0-9]* %\\) meet it only once within the hit epsilon \\(0.00141 units\\): .*; lower --hit-eps \\(e.g. to 1e-7\\) or pass --single-hit exact$"
         -- $<TARGET_FILE:splatcl> csm build ${HOSTILE_DIR}/plate-thin.obj -o ${HOSTILE_DIR}/plate-thin.csm --maps 16 --res 8)
add_test(NAME hostile.csm_thin_closed_part_exact_does_not_warn COMMAND ${EXPECT_OUTPUT} --no-match "warning"
         -- $<TARGET_FILE:splatcl> csm build ${HOSTILE_DIR}/plate-thin.obj -o ${HOSTILE_DIR}/plate-thin-exact.csm --maps 16 --res 8 --single-hit exact)
add_test(NAME hostile.mesh_collapsed_ao_receiver_warns COMMAND ${EXPECT_OUTPUT}
         --match "warning: .*tetra-collapsed.obj: coordinates reach 1000000, where floats step by 0.0625: every vertex reads as the same point"
         -- $<TARGET_FILE:splatcl> ao ${HOSTILE_DIR}/tetra-collapsed.obj --occluder ${HOSTILE_DIR}/tetra-near.csm -o ${HOSTILE_DIR}/collapsed-ao.ply)
set_tests_properties(hostile.mesh_collapsed_ao_receiver_warns PROPERTIES DEPENDS hostile.mesh_near_origin_does_not_warn)
# Numbers beyond float range in a scene (finite as doubles, inf as floats) failed far from the
# field with another cause ("an occluder placement is not invertible", "camera up vector is
# parallel") or drew nothing; splat_scale had no upper bound (k = 10: 260 s of gap covering).
file(WRITE ${HOSTILE_DIR}/position-beyond-float.json "{\"objects\": [{\"name\": \"s\", \"mesh\": {\"procedural\": \"sphere\"}, \"position\": [1e39, 0, 0]}]}")
hostile_error(scene_position_beyond_float "position-beyond-float.json: objects\\[0\\] 's': 'position' must be an array of 3 finite numbers \\(within float range\\)$"
              cluster ${HOSTILE_DIR}/position-beyond-float.json --size 16x16)
file(WRITE ${HOSTILE_DIR}/eye-beyond-float.json "{\"objects\": [], \"camera\": {\"eye\": [0, 1e39, 5], \"target\": [0, 0, 0]}}")
hostile_error(scene_eye_beyond_float "eye-beyond-float.json: camera.eye\\[1\\] is beyond float range" cluster ${HOSTILE_DIR}/eye-beyond-float.json --size 16x16)
file(WRITE ${HOSTILE_DIR}/intensity-beyond-float.json "{\"objects\": [], \"lights\": {\"count\": 4, \"intensity\": 1e39}}")
hostile_error(scene_intensity_beyond_float "intensity-beyond-float.json: lights: 'intensity' must be a finite number \\(within float range"
              cluster ${HOSTILE_DIR}/intensity-beyond-float.json --size 16x16)
file(WRITE ${HOSTILE_DIR}/splat-scale-10.json "{\"objects\": [], \"quality\": {\"splat_scale\": 10}}")
hostile_error(scene_splat_scale_bound "splat-scale-10.json: 'splat_scale' must be in \\[0.25, 3\\], not 10$" cluster ${HOSTILE_DIR}/splat-scale-10.json --size 16x16)
hostile_error(option_render_time_beyond_float "--time 1e\\+39 is not a scene time in seconds \\(finite within float range\\)$" render --time 1e39)
# render --json naming the scene replaced the scene with the timings; cluster -o over a folder
# holding the scene as summary.json likewise.
file(WRITE ${HOSTILE_DIR}/render-own-scene.json "{\"objects\": []}")
hostile_error(render_json_over_scene "--json .*render-own-scene.json would overwrite the scene .*render-own-scene.json$"
              render ${HOSTILE_DIR}/render-own-scene.json --json ${HOSTILE_DIR}/render-own-scene.json --size 16x16)
file(MAKE_DIRECTORY ${HOSTILE_DIR}/cluster-own-scene)
file(WRITE ${HOSTILE_DIR}/cluster-own-scene/summary.json "{\"objects\": []}")
hostile_error(cluster_output_over_scene "-o .*summary.json would overwrite the scene .*summary.json$"
              cluster ${HOSTILE_DIR}/cluster-own-scene/summary.json -o ${HOSTILE_DIR}/cluster-own-scene --size 16x16)
# --cache naming a file failed at the first object, after the device and GL context were set up,
# blamed on that object.
file(WRITE ${HOSTILE_DIR}/cache-is-a-file "not a folder")
hostile_error(render_cache_is_a_file "--cache .*cache-is-a-file: cannot be the asset cache: Not a directory$" render --cache ${HOSTILE_DIR}/cache-is-a-file --size 16x16)
# A refused cluster run removes the -o folders it made (it left them, empty, behind).
add_test(NAME hostile.cluster_refused_run_leaves_no_folder COMMAND sh -c
         "rm -rf \"$1\" && ! \"$0\" cluster --size 4096x4096 --tile 1x1 -o \"$1/made/here\" 2>/dev/null && test ! -e \"$1\""
         $<TARGET_FILE:splatcl> ${HOSTILE_DIR}/cluster-made-folders)
