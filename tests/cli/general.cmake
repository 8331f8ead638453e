# splatcl --help, devices and cluster: the main job runs, bad input gives one line and a non-zero exit.
add_test(NAME cli.help COMMAND ${EXPECT_OUTPUT} --match "^Usage: .*splatcl \\[OPTIONS\\] SUBCOMMAND" --match "^  csm " -- $<TARGET_FILE:splatcl> --help)
foreach(command devices cluster bench)
  add_test(NAME cli.help_${command} COMMAND ${EXPECT_OUTPUT} --match "^Usage: .*splatcl ${command} \\[OPTIONS\\]" -- $<TARGET_FILE:splatcl> ${command} --help)
endforeach()
# One chosen device, with its type; the default scene's light lists lose nothing against brute force.
add_test(NAME cli.devices COMMAND ${EXPECT_OUTPUT} --match "^\\* \\[[0-9]+\\] " --match "^ +type (cpu|gpu|accelerator)" -- $<TARGET_FILE:splatcl> devices)
add_test(NAME cli.cluster_default_scene COMMAND ${EXPECT_OUTPUT} --match "^check +clustered vs brute-force shading: max difference 0 over 1024 lights$"
         --png ${CMAKE_CURRENT_BINARY_DIR}/cli-cluster-out/shaded.png 320 180 --png ${CMAKE_CURRENT_BINARY_DIR}/cli-cluster-out/clusters.png 320 180
         --file ${CMAKE_CURRENT_BINARY_DIR}/cli-cluster-out/summary.json "\"clusters\": [1-9]"
         -- $<TARGET_FILE:splatcl> cluster --size 320x180 -o ${CMAKE_CURRENT_BINARY_DIR}/cli-cluster-out)
add_test(NAME cli.cluster_every_variant COMMAND ${EXPECT_OUTPUT} --match "^grid +13x8 tiles of 16x16, .* with normal-cone bits$"
         --match "^clusters +[1-9][0-9]* occupied .*bitmask$" --match "^lights +300, [1-9][0-9]* list entries \\(brute\\)"
         --match "^check +clustered vs brute-force shading: max difference 0 over 300 lights$"
         -- $<TARGET_FILE:splatcl> cluster --size 200x120 --tile 16x16 --compaction bitmask --assignment brute --normal-bits --window-depth --lights 300)
add_test(NAME cli.error_unknown_command COMMAND ${EXPECT_ERROR} "unknown command 'nonsense' \\(commands: devices, cluster" $<TARGET_FILE:splatcl> nonsense)
# An unknown option before the command is named (CLI11 said "A subcommand is required").
add_test(NAME cli.error_unknown_top_option COMMAND ${EXPECT_ERROR} "^splatcl: unknown option '--bogus' before the command" $<TARGET_FILE:splatcl> --bogus devices)
add_test(NAME cli.error_option_before_command COMMAND ${EXPECT_ERROR} "^splatcl: option '--device' goes after the command" $<TARGET_FILE:splatcl> --device 0 devices)
# A bad progress interval is refused before any work (it was ignored).
add_test(NAME cli.error_bad_progress_interval COMMAND ${EXPECT_ERROR} "SPLATCL_PROGRESS_SECONDS '-1' is not a number of seconds, 0 or more$"
         env SPLATCL_PROGRESS_SECONDS=-1 $<TARGET_FILE:splatcl> devices)
# Naming a simulated device says what to expect (a CSM build at its defaults ran ~20 minutes on
# Oclgrind without a word); another device, none. Skipped (77) without a simulator (--size 0x8
# ends the command right after the note).
add_test(NAME cli.note_simulator_device COMMAND sh -c
         "\"$0\" devices | grep -q '^ *type simulator' || { echo 'no simulated OpenCL device (Oclgrind): skipped'; exit 77; }
          \"$0\" cluster --size 0x8 --device simulator 2>&1 | grep -q '^splatcl: note: a simulated device interprets every operation' &&
          ! \"$0\" cluster --size 0x8 --device cpu 2>&1 | grep -q 'note: a simulated'"
         $<TARGET_FILE:splatcl>)
set_tests_properties(cli.note_simulator_device PROPERTIES SKIP_RETURN_CODE 77)
add_test(NAME cli.error_bad_device COMMAND ${EXPECT_ERROR} "no OpenCL device matches" $<TARGET_FILE:splatcl> devices --device no-such-device)
# The variable is named where the selector came from it (the message read as if --device were wrong).
add_test(NAME cli.error_bad_device_variable COMMAND ${EXPECT_ERROR} "no OpenCL device matches 'no-such-device' \\(from \\$SPLATCL_DEVICE\\)"
         env SPLATCL_DEVICE=no-such-device $<TARGET_FILE:splatcl> cluster --size 8x8)
add_test(NAME cli.error_missing_scene COMMAND ${EXPECT_ERROR} "cannot read scene .*missing.json" $<TARGET_FILE:splatcl> cluster missing.json)
add_test(NAME cli.error_bad_size COMMAND ${EXPECT_ERROR} "--size" $<TARGET_FILE:splatcl> cluster --size 12by7)
add_test(NAME cli.error_bad_compaction COMMAND ${EXPECT_ERROR} "compaction" $<TARGET_FILE:splatcl> cluster --compaction quick)
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/broken-scene.json "{\"objects\": [{\"mesh\": {\"procedural\": \"cone\"}}]}")
add_test(NAME cli.error_broken_scene COMMAND ${EXPECT_ERROR} "broken-scene.json: objects\\[0\\] '[a-z ]*[0-9]*': 'procedural' is 'cone', not one of: sphere, torus, box$"
         $<TARGET_FILE:splatcl> cluster ${CMAKE_CURRENT_BINARY_DIR}/broken-scene.json)
# The scene of render and view: a listed light stays beside --lights generated ones; a splat-file
# object has no mesh to ray cast.
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/cluster-listed-light.json
     "{\"objects\": [{\"mesh\": {\"procedural\": \"box\"}, \"position\": [0, 0.5, 0]}], \"lights\": [{\"position\": [0, 1, 0], \"radius\": 2}]}")
add_test(NAME cli.cluster_listed_and_generated_lights COMMAND ${EXPECT_OUTPUT} --match "^scene +.*cluster-listed-light.json, 1 objects at time 0$"
         --match "^lights +6, [1-9][0-9]* list entries" --match "^check +clustered vs brute-force shading: max difference 0 over 6 lights$"
         -- $<TARGET_FILE:splatcl> cluster ${CMAKE_CURRENT_BINARY_DIR}/cluster-listed-light.json --lights 5 --size 64x48)
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/cluster-splat-object.json "{\"objects\": [{\"name\": \"scan\", \"splats\": \"scan.ply\"}]}")
add_test(NAME cli.error_cluster_splat_object COMMAND ${EXPECT_ERROR} "cluster-splat-object.json: objects\\[0\\] \\(scan\\) is a splat file: the ray caster draws meshes and the floor only$"
         $<TARGET_FILE:splatcl> cluster ${CMAKE_CURRENT_BINARY_DIR}/cluster-splat-object.json)
# A mesh that cannot be read is named with the scene and the object, as render names it.
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/cluster-missing-mesh.json "{\"objects\": [{\"name\": \"torus\", \"mesh\": \"missing.obj\"}]}")
add_test(NAME cli.error_cluster_missing_mesh COMMAND ${EXPECT_ERROR} "cluster-missing-mesh.json: objects\\[0\\] 'torus': cannot read mesh .*missing.obj: no such file$"
         $<TARGET_FILE:splatcl> cluster ${CMAKE_CURRENT_BINARY_DIR}/cluster-missing-mesh.json --size 64x48)
# On a terminal the brute-force check shows its rows (`--lights 300000` was silent for 28 s);
# script(1) gives it one.
add_test(NAME cli.cluster_progress_on_a_terminal COMMAND ${EXPECT_OUTPUT} --match "checking against brute-force shading with 2000 lights: [0-9]+ of 48 rows"
         -- script -qefc "$<TARGET_FILE:splatcl> cluster --lights 2000 --size 64x48" /dev/null)
# A newline in a file name is escaped: the error stays one line (it split the message in two).
add_test(NAME cli.error_newline_in_path COMMAND ${EXPECT_ERROR} "cannot read mesh no\\\\nsuch\\.obj"
         $<TARGET_FILE:splatcl> splats "no\nsuch.obj" -o ${CMAKE_CURRENT_BINARY_DIR}/newline-path.ply)
