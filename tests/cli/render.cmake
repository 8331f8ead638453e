# splatcl render and view: the presenter offscreen and in a window; PRESENT_CACHE and its fixture
# present_cache are set in tests/CMakeLists.txt.
foreach(command render view)
  add_test(NAME cli.help_${command} COMMAND ${EXPECT_OUTPUT} --match "^Usage: .*splatcl ${command} \\[OPTIONS\\]" -- $<TARGET_FILE:splatcl> ${command} --help)
endforeach()
set(RENDER_FRAME "^frame +[0-9.]+ ms = [0-9.]+ fps$")
add_test(NAME cli.render_default_scene COMMAND ${EXPECT_OUTPUT} --match "^scene +default scene .*: 3 objects, [1-9][0-9]* splats, 1024 lights \\(clustered shading, splats mode\\), 160x120$"
         --match "^clusters +[1-9][0-9]* with [1-9][0-9]* light indices" --match "${RENDER_FRAME}" --png ${CMAKE_CURRENT_BINARY_DIR}/render-default.png 160 120
         --file ${CMAKE_CURRENT_BINARY_DIR}/render-default.json "\"frames_measured\": 2,"
         --file ${CMAKE_CURRENT_BINARY_DIR}/render-default.json "\"name\": \"torus\","
         --file ${CMAKE_CURRENT_BINARY_DIR}/render-default.json "\"csm_maps\": 1024,"
         --file ${CMAKE_CURRENT_BINARY_DIR}/render-default.json "\"csm_single_hit\": \"sphere-exit\","
         --file ${CMAKE_CURRENT_BINARY_DIR}/render-default.json "\"csm_segments\": [1-9][0-9]*,"
         --file ${CMAKE_CURRENT_BINARY_DIR}/render-default.json "\"debug_view\": \"final\","
         --file ${CMAKE_CURRENT_BINARY_DIR}/render-default.json "\"filter\": \"march\","
         --file ${CMAKE_CURRENT_BINARY_DIR}/render-default.json "\"floor_pixels\": true,"
         --file ${CMAKE_CURRENT_BINARY_DIR}/render-default.json "\"splat_scale\": 1\\.0499999[0-9]*,?$"
         -- $<TARGET_FILE:splatcl> render --size 160x120 --frames 3 --cache ${PRESENT_CACHE} -o ${CMAKE_CURRENT_BINARY_DIR}/render-default.png
         --json ${CMAKE_CURRENT_BINARY_DIR}/render-default.json)
add_test(NAME cli.render_tiled_points_exr COMMAND ${EXPECT_OUTPUT} --match "\\(tiled shading, points mode\\), 120x90$" --exr ${CMAKE_CURRENT_BINARY_DIR}/render-points.exr
         -- $<TARGET_FILE:splatcl> render --size 120x90 --shading tiled --mode points --shadows pixel --pixel-ao --view final
         --cache ${PRESENT_CACHE} -o ${CMAKE_CURRENT_BINARY_DIR}/render-points.exr)
add_test(NAME cli.render_no_display COMMAND ${EXPECT_OUTPUT} --match " 64 lights \\(brute shading, splats mode\\), 64x48$" --match "${RENDER_FRAME}"
         -- env -u DISPLAY -u WAYLAND_DISPLAY $<TARGET_FILE:splatcl> render --size 64x48 --shading brute --lights 64 --view clusters
         --cache ${PRESENT_CACHE})
# --json reports the lengths the frame used: a scene without depth_offset and shadow_lift scales them
# to its smallest object (0.02 would be half a 1e-3 sphere; the JSON said 0.02 before).
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/present-small-scene.json "{\"objects\": [{\"name\": \"small\", \"mesh\": {\"procedural\": \"sphere\"}, \"scale\": 0.001}]}")
add_test(NAME cli.render_json_reports_the_scaled_lengths COMMAND ${EXPECT_OUTPUT} --match "${RENDER_FRAME}"
         --file ${CMAKE_CURRENT_BINARY_DIR}/render-small.json "\"depth_offset\": 3\\.464[0-9]*e-05,"
         --file ${CMAKE_CURRENT_BINARY_DIR}/render-small.json "\"shadow_lift\": 3\\.464[0-9]*e-05,"
         -- $<TARGET_FILE:splatcl> render ${CMAKE_CURRENT_BINARY_DIR}/present-small-scene.json --size 64x48 --frames 2
         --cache ${PRESENT_CACHE} --json ${CMAKE_CURRENT_BINARY_DIR}/render-small.json)
set_tests_properties(cli.render_default_scene cli.render_tiled_points_exr cli.render_no_display cli.render_json_reports_the_scaled_lengths
                     PROPERTIES FIXTURES_REQUIRED present_cache)
add_test(NAME cli.render_wall_passes COMMAND ${EXPECT_OUTPUT} --match "gl: splat accumulation +[0-9.]+" -- $<TARGET_FILE:splatcl> render --size 64x48 --frames 2
         --wall-passes --cache ${PRESENT_CACHE})
add_test(NAME cli.render_lod COMMAND ${EXPECT_OUTPUT} --match "splats drawn \\(LOD 2 px\\)" -- $<TARGET_FILE:splatcl> render --size 96x72 --lod 2 --mode points
         --cache ${PRESENT_CACHE})
set_tests_properties(cli.render_wall_passes cli.render_lod PROPERTIES FIXTURES_REQUIRED present_cache)
add_test(NAME cli.error_render_bad_lod COMMAND ${EXPECT_ERROR} "--lod" $<TARGET_FILE:splatcl> render --lod -1)
add_test(NAME cli.render_specular COMMAND ${EXPECT_OUTPUT} --match "${RENDER_FRAME}" --png ${CMAKE_CURRENT_BINARY_DIR}/render-specular.png 64 48
         -- $<TARGET_FILE:splatcl> render --size 64x48 --specular 0.5 --cache ${PRESENT_CACHE} -o ${CMAKE_CURRENT_BINARY_DIR}/render-specular.png)
set_tests_properties(cli.render_specular PROPERTIES FIXTURES_REQUIRED present_cache)
# The march shadow test from the command line (its image properties: csm.CsmVisibility.March*).
add_test(NAME cli.render_filter_march COMMAND ${EXPECT_OUTPUT} --match "${RENDER_FRAME}" --png ${CMAKE_CURRENT_BINARY_DIR}/render-march.png 64 48
         -- $<TARGET_FILE:splatcl> render --size 64x48 --filter march --shadows pixel --cache ${PRESENT_CACHE} -o ${CMAKE_CURRENT_BINARY_DIR}/render-march.png)
set_tests_properties(cli.render_filter_march PROPERTIES FIXTURES_REQUIRED present_cache)
add_test(NAME cli.error_render_bad_filter COMMAND ${EXPECT_ERROR} "--filter: unknown filter 'soft' \\(one of: none, same-map, cross-map, march\\)"
         $<TARGET_FILE:splatcl> render --filter soft)
add_test(NAME cli.error_render_bad_specular COMMAND ${EXPECT_ERROR} "--specular" $<TARGET_FILE:splatcl> render --specular -1)
add_test(NAME cli.error_render_missing_scene COMMAND ${EXPECT_ERROR} "cannot read scene .*missing.json" $<TARGET_FILE:splatcl> render missing.json)
add_test(NAME cli.error_render_bad_size COMMAND ${EXPECT_ERROR} "--size '12by7'" $<TARGET_FILE:splatcl> render --size 12by7)
add_test(NAME cli.error_render_bad_output COMMAND ${EXPECT_ERROR} "-o frame.tiff: the file must end in .png or .exr \\(the image\\)" $<TARGET_FILE:splatcl> render -o frame.tiff)
add_test(NAME cli.error_render_missing_output_dir COMMAND ${EXPECT_ERROR} "directory no-such-dir does not exist" $<TARGET_FILE:splatcl> render -o no-such-dir/frame.png)
add_test(NAME cli.error_render_bad_shading COMMAND ${EXPECT_ERROR} "--shading 'quick'" $<TARGET_FILE:splatcl> render --shading quick)
add_test(NAME cli.error_render_bad_view COMMAND ${EXPECT_ERROR} "unknown view 'wireframe'" $<TARGET_FILE:splatcl> render --view wireframe)
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/present-broken-scene.json "{\"objects\": [{\"mesh\": {\"procedural\": \"cone\"}}]}")
add_test(NAME cli.error_render_broken_scene COMMAND ${EXPECT_ERROR} "present-broken-scene.json: objects\\[0\\] 'object 0': 'procedural'" $<TARGET_FILE:splatcl>
         render ${CMAKE_CURRENT_BINARY_DIR}/present-broken-scene.json)
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/present-missing-mesh.json "{\"objects\": [{\"mesh\": \"no-such-mesh.obj\"}]}")
add_test(NAME cli.error_render_missing_mesh COMMAND ${EXPECT_ERROR} "no-such-mesh.obj" $<TARGET_FILE:splatcl>
         render ${CMAKE_CURRENT_BINARY_DIR}/present-missing-mesh.json --cache ${PRESENT_CACHE})
# An object placed where floats step by more than 1/256 of its size is refused before its assets are
# built, naming it (at 1e7 a unit sphere vanished from the frame with no word; at 1e6 it cracked).
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/present-far-scene.json
     "{\"objects\": [{\"name\": \"far ball\", \"mesh\": {\"procedural\": \"sphere\"}, \"position\": [1e7, 1e7, 1e7]}], \"camera\": {\"eye\": [1e7, 1e7, 10000003], \"target\": [1e7, 1e7, 1e7]}}")
add_test(NAME cli.error_render_far_object COMMAND ${EXPECT_ERROR}
         "present-far-scene.json: objects\\[0\\] 'far ball': placed where coordinates reach 1e\\+07, where floats step by 1 \\(29 % of its 3.464 size\\).*breaks it up"
         $<TARGET_FILE:splatcl> render ${CMAKE_CURRENT_BINARY_DIR}/present-far-scene.json --size 32x24 --cache ${PRESENT_CACHE})
# A scale of 1e-11 is within the documented range: its placement was refused as "not invertible"
# (an absolute determinant threshold), naming no object.
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/present-tiny-scene.json
     "{\"objects\": [{\"name\": \"tiny\", \"mesh\": {\"procedural\": \"sphere\"}, \"scale\": 1e-11}], \"camera\": {\"eye\": [0, 2e-11, 4e-11], \"target\": [0, 0, 0], \"near\": 1e-12, \"far\": 1e-9}}")
add_test(NAME cli.render_tiny_scale COMMAND ${EXPECT_OUTPUT} --match "${RENDER_FRAME}"
         -- $<TARGET_FILE:splatcl> render ${CMAKE_CURRENT_BINARY_DIR}/present-tiny-scene.json --size 32x24 --cache ${PRESENT_CACHE})
set_tests_properties(cli.error_render_far_object cli.render_tiny_scale PROPERTIES FIXTURES_REQUIRED present_cache)
add_test(NAME cli.error_view_no_display COMMAND ${EXPECT_ERROR} "GLFW: cannot" env -u DISPLAY -u WAYLAND_DISPLAY
         $<TARGET_FILE:splatcl> view --cache ${PRESENT_CACHE})
find_program(XVFB_RUN xvfb-run)
if(XVFB_RUN)
  add_test(NAME cli.view_window COMMAND ${EXPECT_OUTPUT} --match "^keys: left drag orbit" -- ${XVFB_RUN} -a $<TARGET_FILE:splatcl> view --size 160x120
           --seconds 2 --cache ${PRESENT_CACHE})
  add_test(NAME cli.view_panel_leaves_the_image COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cli/view_panel_test.sh $<TARGET_FILE:splatcl>
           ${PRESENT_CACHE} ${CMAKE_CURRENT_BINARY_DIR}/view-panel)
  add_test(NAME cli.view_input_xvfb COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/cli/view_input_test.sh $<TARGET_FILE:splatcl> ${PRESENT_CACHE})
  set_tests_properties(cli.view_window cli.view_panel_leaves_the_image cli.view_input_xvfb PROPERTIES FIXTURES_REQUIRED present_cache)
  set_tests_properties(cli.view_input_xvfb PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 300)
  # SIGINT ends the loop after its frame: the run prints its summary and state (it died without a
  # word) and exits 130.
  add_test(NAME cli.view_sigint_prints_state COMMAND ${XVFB_RUN} -a bash -c
           "command -v xdotool >/dev/null || exit 77; \"$1\" view --size 160x120 --seconds 120 --cache \"$2\" > \"$3\" 2>&1 & pid=$!; timeout 120 xdotool search --sync --name '^splatcl view' >/dev/null || exit 1; sleep 1; kill -INT $pid; wait $pid; rc=$?; grep -q '^view: state ' \"$3\" && grep -q '^view: ended by signal 2' \"$3\" && test $rc -eq 130"
           bash $<TARGET_FILE:splatcl> ${PRESENT_CACHE} ${CMAKE_CURRENT_BINARY_DIR}/view-sigint.log)
  set_tests_properties(cli.view_sigint_prints_state PROPERTIES FIXTURES_REQUIRED present_cache SKIP_RETURN_CODE 77 TIMEOUT 180)
endif()
add_test(NAME cli.error_view_screenshot_on_exit_needs_seconds COMMAND ${EXPECT_ERROR} "--screenshot-on-exit needs --seconds"
         $<TARGET_FILE:splatcl> view --screenshot-on-exit)
add_test(NAME cli.error_view_bad_seconds COMMAND ${EXPECT_ERROR} "--seconds -1 is not a duration" $<TARGET_FILE:splatcl> view --seconds -1)
add_test(NAME cli.error_view_missing_screenshots_dir COMMAND ${EXPECT_ERROR} "--screenshots no-such-dir: no such directory$"
         $<TARGET_FILE:splatcl> view --screenshots no-such-dir)
# The shipped scene of scanned models (data/scans-scene.json) with the test models linked beside a
# copy of it, as a user links them into data/models: each scan built with the scene's defaults, a
# line per built step, and both objects in the figures. Skipped without the test models.
set(SCANS_DIR ${CMAKE_CURRENT_BINARY_DIR}/scans-scene)
file(MAKE_DIRECTORY ${SCANS_DIR})
configure_file(${PROJECT_SOURCE_DIR}/data/scans-scene.json ${SCANS_DIR}/scans-scene.json COPYONLY)
if(EXISTS ${SPLATCL_MODELS_DIR} AND NOT EXISTS ${SCANS_DIR}/models)
  file(CREATE_LINK ${SPLATCL_MODELS_DIR} ${SCANS_DIR}/models SYMBOLIC)
endif()
add_test(NAME cli.render_scans_scene COMMAND ${NEEDS_FILE} ${SPLATCL_MODELS_DIR}/nefertiti.obj ${EXPECT_OUTPUT}
         --match "^render: built bunny: [1-9][0-9]* splats from 69451 faces in [0-9.]+ s$"
         --match "^render: built nefertiti: coherent shadow map of 1024 maps of 64² in [0-9.]+ s$"
         --match "^scene .*scans-scene.json: 3 objects, [1-9][0-9]* splats, 256 lights"
         --file ${SCANS_DIR}/render.json "\"name\": \"nefertiti\","
         --file ${SCANS_DIR}/render.json "\"source\": \"mesh models/stanford-bunny.obj\","
         --png ${SCANS_DIR}/render.png 160 120
         -- $<TARGET_FILE:splatcl> render ${SCANS_DIR}/scans-scene.json --size 160x120 --frames 2 --cache ${SCANS_DIR}/cache
         -o ${SCANS_DIR}/render.png --json ${SCANS_DIR}/render.json)
# A cold cache each run, so the build lines are there to check.
add_test(NAME cli.render_scans_scene_cold_cache COMMAND ${CMAKE_COMMAND} -E rm -rf ${SCANS_DIR}/cache)
set_tests_properties(cli.render_scans_scene_cold_cache PROPERTIES FIXTURES_SETUP scans_cold_cache)
set_tests_properties(cli.render_scans_scene PROPERTIES SKIP_RETURN_CODE 77 FIXTURES_REQUIRED scans_cold_cache)
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/present-missing-splats.json "{\"objects\": [{\"splats\": \"no-such.ply\"}]}")
add_test(NAME cli.error_render_missing_splat_file COMMAND ${EXPECT_ERROR} "cannot read splat file .*no-such.ply"
         $<TARGET_FILE:splatcl> render ${CMAKE_CURRENT_BINARY_DIR}/present-missing-splats.json)
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/present-not-splats.ply "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n")
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/present-not-splats.json "{\"objects\": [{\"splats\": \"present-not-splats.ply\"}]}")
add_test(NAME cli.error_render_point_cloud_as_splats COMMAND ${EXPECT_ERROR} "cannot read 3D Gaussian Splatting file .*present-not-splats.ply: the vertex element has no 'scale_0' property"
         $<TARGET_FILE:splatcl> render ${CMAKE_CURRENT_BINARY_DIR}/present-not-splats.json)
# --json and --cache naming one path: refused before the cache folder is made (it was, and the
# assets built, before writing the JSON failed).
add_test(NAME cli.error_render_json_is_cache COMMAND ${EXPECT_ERROR} "--json and --cache name the same file .*render-same-path"
         $<TARGET_FILE:splatcl> render --size 64x48 --json ${CMAKE_CURRENT_BINARY_DIR}/render-same-path --cache ${CMAKE_CURRENT_BINARY_DIR}/render-same-path)
add_test(NAME cli.error_render_json_is_cache_with_slash COMMAND ${EXPECT_ERROR} "--json and --cache name the same file .*render-same-path-2/"
         $<TARGET_FILE:splatcl> render --size 64x48 --json ${CMAKE_CURRENT_BINARY_DIR}/render-same-path-2 --cache ${CMAKE_CURRENT_BINARY_DIR}/render-same-path-2/)
