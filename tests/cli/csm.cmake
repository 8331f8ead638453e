# splatcl csm: a generated cube built, described, verified (losslessness), then bad input.
set(CSM_OUT ${CMAKE_CURRENT_BINARY_DIR}/csm-cube.csm)
add_test(NAME cli.help_csm COMMAND ${EXPECT_OUTPUT} --match "^Usage: .*splatcl csm \\[OPTIONS\\] SUBCOMMAND" -- $<TARGET_FILE:splatcl> csm --help)
add_test(NAME cli.help_csm_build COMMAND ${EXPECT_OUTPUT} --match "^Usage: .*splatcl csm build \\[OPTIONS\\]" -- $<TARGET_FILE:splatcl> csm build --help)
add_test(NAME cli.csm_build_cube COMMAND ${EXPECT_OUTPUT} --match "^maps +256 = 16 x 16 \\(uniform distribution, zigzag-h order, pole y\\), 32x32 pixels$"
         --match "^segments +[1-9][0-9]* " --match "^wrote +.*csm-cube.csm \\(plain encoding\\)" --png ${CMAKE_CURRENT_BINARY_DIR}/csm-cube-coherence.png 32 32
         -- $<TARGET_FILE:splatcl> csm build ${SPLATS_CUBE} -o ${CSM_OUT} --maps 256 --res 32 --batch 50 --coherence ${CMAKE_CURRENT_BINARY_DIR}/csm-cube-coherence.png)
set_tests_properties(cli.csm_build_cube PROPERTIES FIXTURES_SETUP csm_cube)
add_test(NAME cli.csm_build_cube_compact COMMAND ${EXPECT_OUTPUT} --match "^maps +128 = 8 x 16 \\(ao distribution, zigzag-v order, pole y\\), 16x16 pixels$"
         --match "single-surface pixels: exact;" --match "^wrote +.*csm-cube-compact.csm \\(compact encoding\\)$"
         -- $<TARGET_FILE:splatcl> csm build ${SPLATS_CUBE} -o ${CMAKE_CURRENT_BINARY_DIR}/csm-cube-compact.csm --maps 128 --res 16 --dist ao --order zigzag-v
         --encoding compact --single-hit exact)
set_tests_properties(cli.csm_build_cube_compact PROPERTIES FIXTURES_SETUP csm_cube)
add_test(NAME cli.csm_info COMMAND ${EXPECT_OUTPUT} --match "^model +.*splats-cube.obj \\(12 triangles\\)$" --match "^maps +256 = 16 x 16 .*, 32x32 pixels$"
         --match "^file +plain encoding, [1-9][0-9]* bytes" -- $<TARGET_FILE:splatcl> csm info ${CSM_OUT})
set(CSM_LOSSLESS "^lossless +all [1-9][0-9]* \\(map, pixel\\) samples of .* keep their depth-test result")
add_test(NAME cli.csm_verify COMMAND ${EXPECT_OUTPUT} --match "^file +.*csm-cube.csm: valid \\(plain encoding, [1-9][0-9]* segments, 256 maps of 32x32\\)$"
         --match "^lossless +all 262144 \\(map, pixel\\)" -- $<TARGET_FILE:splatcl> csm verify ${CSM_OUT} ${SPLATS_CUBE})
add_test(NAME cli.csm_verify_compact COMMAND ${EXPECT_OUTPUT} --match "valid \\(compact encoding, [1-9][0-9]* segments, 128 maps of 16x16\\)$"
         --match "^lossless +all 32768 \\(map, pixel\\)" -- $<TARGET_FILE:splatcl> csm verify ${CMAKE_CURRENT_BINARY_DIR}/csm-cube-compact.csm ${SPLATS_CUBE} --reference)
# With another model: one line saying the CSM was not built from it (it said "not lossless" and
# blamed the file).
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/csm-other.obj "v 0 0 0\nv 2 0 0\nv 0 2 0\nv 0 0 2\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
add_test(NAME cli.error_csm_verify_other_model COMMAND ${EXPECT_ERROR} "^splatcl: the CSM was not built from .*csm-other.obj: its bounding sphere"
         $<TARGET_FILE:splatcl> csm verify ${CSM_OUT} ${CMAKE_CURRENT_BINARY_DIR}/csm-other.obj)
set_tests_properties(cli.csm_info cli.csm_verify cli.csm_verify_compact cli.error_csm_verify_other_model PROPERTIES FIXTURES_REQUIRED csm_cube)
# Both capture methods: a ray-cast build verifies by the method recorded in its header; a bad method name is an error.
add_test(NAME cli.csm_build_cube_raycast COMMAND ${EXPECT_OUTPUT} --match "^capture +raycast$" --match "^wrote +.*csm-cube-raycast.csm"
         -- $<TARGET_FILE:splatcl> csm build ${SPLATS_CUBE} -o ${CMAKE_CURRENT_BINARY_DIR}/csm-cube-raycast.csm --maps 64 --res 16 --capture raycast)
set_tests_properties(cli.csm_build_cube_raycast PROPERTIES FIXTURES_SETUP csm_cube_raycast)
add_test(NAME cli.csm_verify_raycast COMMAND splatcl csm verify ${CMAKE_CURRENT_BINARY_DIR}/csm-cube-raycast.csm ${SPLATS_CUBE})
set_tests_properties(cli.csm_verify_raycast PROPERTIES PASS_REGULAR_EXPRESSION "recaptured by raycast, as recorded in the file")
set_tests_properties(cli.csm_verify_raycast PROPERTIES FIXTURES_REQUIRED csm_cube_raycast)
# A build that outgrows the memory it may use stops with the cause (SPLATCL_MEMORY_LIMIT counts the
# process's resident set, far above 1 MiB) instead of being killed for memory; nothing is written.
add_test(NAME cli.error_csm_memory_limit COMMAND ${EXPECT_ERROR}
         "^splatcl: the CSM build at resolution 64 with 64 maps \\(its compressed maps hold [0-9.]+ [KMG]iB after [0-9]+ maps\\) needs about [0-9.]+ [KMG]iB more memory, and 0 bytes is available within SPLATCL_MEMORY_LIMIT: lower the resolution or the map count$"
         sh -c "\"$<TARGET_FILE:splatcl>\" csm build ${SPLATS_CUBE} -o memory.csm --res 64 --maps 64 && exit 0; status=$?; [ ! -e memory.csm ] || exit 0; exit $status")
set_tests_properties(cli.error_csm_memory_limit PROPERTIES ENVIRONMENT SPLATCL_MEMORY_LIMIT=1M)
add_test(NAME cli.error_memory_limit_syntax COMMAND ${EXPECT_ERROR} "^splatcl: SPLATCL_MEMORY_LIMIT '2GB' is not a byte count \\(digits, optionally followed by K, M, G or T\\)$"
         $<TARGET_FILE:splatcl> csm build ${SPLATS_CUBE} -o syntax.csm --res 16 --maps 16)
set_tests_properties(cli.error_memory_limit_syntax PROPERTIES ENVIRONMENT SPLATCL_MEMORY_LIMIT=2GB)
add_test(NAME cli.error_csm_bad_capture COMMAND ${EXPECT_ERROR} "unknown capture method 'rays'" $<TARGET_FILE:splatcl> csm build ${SPLATS_CUBE} -o out.csm --capture rays)
add_test(NAME cli.error_csm_missing_model COMMAND ${EXPECT_ERROR} "cannot read mesh .*missing.obj" $<TARGET_FILE:splatcl> csm build missing.obj -o out.csm)
add_test(NAME cli.error_csm_no_output COMMAND ${EXPECT_ERROR} "-o OUT.csm" $<TARGET_FILE:splatcl> csm build ${SPLATS_CUBE})
add_test(NAME cli.error_csm_bad_maps COMMAND ${EXPECT_ERROR} "^splatcl: '--maps': 1000 is not a perfect square, as the uniform G x G grid needs" $<TARGET_FILE:splatcl> csm build ${SPLATS_CUBE} -o out.csm --maps 1000)
add_test(NAME cli.error_csm_bad_order COMMAND ${EXPECT_ERROR} "unknown map order 'spiral'" $<TARGET_FILE:splatcl> csm build ${SPLATS_CUBE} -o out.csm --order spiral)
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/csm-degenerate.obj "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n")
add_test(NAME cli.error_csm_degenerate_model COMMAND ${EXPECT_ERROR} "csm-degenerate.obj: every face is degenerate" $<TARGET_FILE:splatcl>
         csm build ${CMAKE_CURRENT_BINARY_DIR}/csm-degenerate.obj -o out.csm --maps 16 --res 8)
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/csm-truncated.csm "SPLATCSM")
add_test(NAME cli.error_csm_truncated COMMAND ${EXPECT_ERROR} "csm-truncated.csm: not a .csm file" $<TARGET_FILE:splatcl> csm info ${CMAKE_CURRENT_BINARY_DIR}/csm-truncated.csm)
add_test(NAME cli.error_csm_missing_file COMMAND ${EXPECT_ERROR} "cannot read missing.csm" $<TARGET_FILE:splatcl> csm verify missing.csm)
# splatcl csm quality: the shadow-quality study on the generated cube, then a bad filter name.
add_test(NAME cli.csm_quality_cube COMMAND ${EXPECT_OUTPUT} --match "^study +2 views of 32x32 pixels, .*filter cross-map"
         --match "^wrong +[0-9.]+ % of image pixels, [0-9.]+ % of object pixels \\([0-9]+ of [1-9][0-9]* object pixels"
         --match "^queries +[1-9][0-9]* CSM visibility queries" -- $<TARGET_FILE:splatcl> csm quality ${SPLATS_CUBE} --maps 64 --res 16 --views 2 --image 32 --filter cross-map)
add_test(NAME cli.csm_quality_cube_march COMMAND ${EXPECT_OUTPUT} --match "^study +2 views of 32x32 pixels, .*filter march"
         --match "^wrong +[0-9.]+ % of image pixels" -- $<TARGET_FILE:splatcl> csm quality ${SPLATS_CUBE} --maps 64 --res 16 --views 2 --image 32 --filter march)
add_test(NAME cli.error_csm_quality_bad_filter COMMAND ${EXPECT_ERROR} "unknown filter 'gauss'" $<TARGET_FILE:splatcl> csm quality ${SPLATS_CUBE} --maps 64 --res 16 --filter gauss)

# csm build --mode: the thesis's alternatives (sizes only, every sample checked), csm analyze.
set(CSM_MODE_LOSSLESS "^lossless +all [1-9][0-9]* \\(map, pixel\\) samples decode through the mode's lookup to a depth in \\[z1, z2\\)$")
add_test(NAME cli.csm_mode_per_map COMMAND ${EXPECT_OUTPUT} --match "^mode +per-map \\(pixel order zigzag-h\\) on 64 maps of 16x16" --match "^segments +[1-9][0-9]* in 64 lists"
         --match "${CSM_MODE_LOSSLESS}" -- $<TARGET_FILE:splatcl> csm build ${SPLATS_CUBE} --mode per-map --pixel-order zigzag-h --maps 64 --res 16)
add_test(NAME cli.csm_mode_hilbert_3d COMMAND ${EXPECT_OUTPUT} --match "^mode +hilbert-3d on 36 maps of 8x8" --match "${CSM_MODE_LOSSLESS}"
         -- $<TARGET_FILE:splatcl> csm build ${SPLATS_CUBE} --mode hilbert-3d --maps 36 --res 8)
add_test(NAME cli.csm_mode_hilbert_4d COMMAND ${EXPECT_OUTPUT} --match "^mode +hilbert-4d on 64 maps of 8x8" --match "^segments +[1-9][0-9]* in 1 lists"
         --match "${CSM_MODE_LOSSLESS}" -- $<TARGET_FILE:splatcl> csm build ${SPLATS_CUBE} --mode hilbert-4d --maps 64 --res 8 --reference)
# k = the map count reproduces the per-pixel build exactly: no wrong sample.
add_test(NAME cli.csm_analyze COMMAND ${EXPECT_OUTPUT} --match "^per-pixel +[1-9][0-9]* segments" --match "^wavelet +[1-9][0-9]* layers x 2"
         --match "^k-means +k = +4: .*wrong samples [0-9]+ " --match "^k-means +k = +64: .*wrong samples 0 \\(0.000 %\\)"
         -- $<TARGET_FILE:splatcl> csm analyze ${SPLATS_CUBE} --maps 64 --res 16 --kmeans 4 --kmeans 64 --wavelet)
add_test(NAME cli.error_csm_bad_mode COMMAND ${EXPECT_ERROR} "unknown compression mode 'octree'" $<TARGET_FILE:splatcl> csm build ${SPLATS_CUBE} --mode octree)
add_test(NAME cli.error_csm_mode_output COMMAND ${EXPECT_ERROR} "only measures sizes" $<TARGET_FILE:splatcl> csm build ${SPLATS_CUBE} --mode per-map -o out.csm)
add_test(NAME cli.error_csm_mode_hilbert_res COMMAND ${EXPECT_ERROR} "power-of-two resolution, not 12" $<TARGET_FILE:splatcl> csm build ${SPLATS_CUBE}
         --mode per-map --maps 16 --res 12)
# A resolution the wavelet analysis cannot take is refused before the build (it was refused after
# the capture and the k-means runs, whose results it hid): nothing on stdout.
add_test(NAME cli.error_csm_analyze_wavelet_resolution COMMAND sh -c
         "if \"$0\" csm analyze \"$1\" --maps 16 --res 6 --wavelet --kmeans 1 > \"$2.out\" 2> \"$2.err\"; then exit 1; fi; cat \"$2.err\"; [ ! -s \"$2.out\" ] && grep -q '^splatcl: the Haar-wavelet analysis needs a power-of-two resolution (--res), not 6$' \"$2.err\""
         $<TARGET_FILE:splatcl> ${SPLATS_CUBE} ${CMAKE_CURRENT_BINARY_DIR}/csm-analyze-wavelet)
add_test(NAME cli.error_csm_analyze_nothing COMMAND ${EXPECT_ERROR} "--kmeans K" $<TARGET_FILE:splatcl> csm analyze ${SPLATS_CUBE} --maps 16 --res 8)
add_test(NAME cli.error_csm_analyze_big_k COMMAND ${EXPECT_ERROR} "^splatcl: --kmeans 32 is more clusters than the 16 maps \\(--maps\\)$" $<TARGET_FILE:splatcl> csm analyze
         ${SPLATS_CUBE} --maps 16 --res 8 --kmeans 32)
# --iterations 0 crashed (no map had a cluster); --kmeans 0 failed only after the build.
add_test(NAME cli.error_csm_analyze_no_iterations COMMAND ${EXPECT_ERROR} "--iterations: '0' is not in 1..1000000" $<TARGET_FILE:splatcl> csm analyze
         ${SPLATS_CUBE} --maps 16 --res 8 --kmeans 4 --iterations 0)
add_test(NAME cli.error_csm_analyze_zero_k COMMAND ${EXPECT_ERROR} "--kmeans: '0' is not in 1..4294967295" $<TARGET_FILE:splatcl> csm analyze
         ${SPLATS_CUBE} --maps 16 --res 8 --kmeans 0)
# An output that names an input, or the wrong kind of file, is refused before any work (the model
# stays as it was; a copy written here is the input).
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/csm-overwrite-me.obj "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
add_test(NAME cli.error_csm_output_is_model COMMAND ${EXPECT_ERROR} "-o .*csm-overwrite-me.obj would overwrite the model" $<TARGET_FILE:splatcl>
         csm build ${CMAKE_CURRENT_BINARY_DIR}/csm-overwrite-me.obj -o ${CMAKE_CURRENT_BINARY_DIR}/csm-overwrite-me.obj)
add_test(NAME cli.error_csm_output_extension COMMAND ${EXPECT_ERROR} "-o out.txt: the file must end in .csm" $<TARGET_FILE:splatcl>
         csm build ${SPLATS_CUBE} -o out.txt)
# csm quality with a CSM of another model (the tetrahedron against the cube's map): refused, not scored.
add_test(NAME cli.error_csm_quality_other_model COMMAND ${EXPECT_ERROR} "the CSM was not built from .*csm-overwrite-me.obj" $<TARGET_FILE:splatcl>
         csm quality ${CMAKE_CURRENT_BINARY_DIR}/csm-overwrite-me.obj --csm ${CSM_OUT} --views 1 --image 16)
set_tests_properties(cli.error_csm_quality_other_model PROPERTIES FIXTURES_REQUIRED csm_cube)
# A coherence map that is no image: csm info printed its whole report and then failed.
add_test(NAME cli.error_csm_info_coherence_not_an_image COMMAND ${EXPECT_ERROR} "^splatcl: --coherence .*coh.txt: the file must end in .png or .exr \\(the coherence map image\\)$"
         $<TARGET_FILE:splatcl> csm info ${CSM_OUT} --coherence ${CMAKE_CURRENT_BINARY_DIR}/coh.txt)
set_tests_properties(cli.error_csm_info_coherence_not_an_image PROPERTIES FIXTURES_REQUIRED csm_cube)
add_test(NAME cli.error_csm_build_coherence_not_an_image COMMAND ${EXPECT_ERROR} "^splatcl: --coherence .*coh.txt: the file must end in .png or .exr"
         $<TARGET_FILE:splatcl> csm build ${SPLATS_CUBE} -o ${CMAKE_CURRENT_BINARY_DIR}/coh-build.csm --maps 16 --res 8 --coherence ${CMAKE_CURRENT_BINARY_DIR}/coh.txt)
# csm quality --csm FILE ignored the build options silently.
add_test(NAME cli.error_csm_quality_csm_with_build_options COMMAND ${EXPECT_ERROR} "--csm .*csm-cube.csm: the build options --maps do not apply to a CSM read from a file"
         $<TARGET_FILE:splatcl> csm quality ${SPLATS_CUBE} --csm ${CSM_OUT} --maps 16)
set_tests_properties(cli.error_csm_quality_csm_with_build_options PROPERTIES FIXTURES_REQUIRED csm_cube)
# Progress in a log (stderr not a terminal): plain lines at most every SPLATCL_PROGRESS_SECONDS
# (default 30, the first once the work has run that long), so a long build shows movement in a
# job's log; here at 0 s, every step is a line.
add_test(NAME cli.progress_lines_in_a_log COMMAND ${EXPECT_OUTPUT} --match "^csm: .*maps"
         -- env SPLATCL_PROGRESS_SECONDS=0 $<TARGET_FILE:splatcl> csm build ${SPLATS_CUBE} -o ${CMAKE_CURRENT_BINARY_DIR}/csm-progress.csm --maps 256 --res 16 --batch 64)
add_test(NAME cli.no_progress_lines_in_a_short_log COMMAND ${EXPECT_OUTPUT} --no-match "^csm: "
         -- $<TARGET_FILE:splatcl> csm build ${SPLATS_CUBE} -o ${CMAKE_CURRENT_BINARY_DIR}/csm-progress-short.csm --maps 256 --res 16 --batch 64)
