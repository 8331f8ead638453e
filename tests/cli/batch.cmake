# splatcl batch: --help, one-line manifest errors, then tests/batch/cli_*.sh drive whole runs
# (interrupted and resumed, sharded and merged, with failing models) on tiny generated meshes.
set(BATCH_DIR ${CMAKE_CURRENT_BINARY_DIR}/batch-cli)
add_test(NAME cli.help_batch COMMAND ${EXPECT_OUTPUT} --match "^Usage: .*splatcl batch \\[OPTIONS\\]" -- $<TARGET_FILE:splatcl> batch --help)
add_test(NAME cli.help_batch_merge COMMAND ${EXPECT_OUTPUT} --match "^Usage: .*splatcl batch merge \\[OPTIONS\\]" -- $<TARGET_FILE:splatcl> batch merge --help)
file(WRITE ${BATCH_DIR}/bad.json "{\"models\": [\"a.obj\",]}")
file(WRITE ${BATCH_DIR}/unknown-key.json "{\"models\": [{\"path\": \"a.obj\", \"epsilon\": 1}]}")
file(WRITE ${BATCH_DIR}/bad-value.csv "path,k\na.obj,zero\n")
file(WRITE ${BATCH_DIR}/ok.csv "path\na.obj\n")
file(WRITE ${BATCH_DIR}/not-summary.json "{\"models\": []}")
file(WRITE ${BATCH_DIR}/case.json "{\"models\": [{\"path\": \"a.obj\", \"id\": \"Chair\"}, {\"path\": \"a.obj\", \"id\": \"chair\"}]}")
add_test(NAME cli.batch_ids_differing_in_case_warn COMMAND ${EXPECT_OUTPUT}
         --match "^splatcl: warning: .*case.json: model ids 'Chair' and 'chair' differ only in letter case: on a case-insensitive file system"
         -- $<TARGET_FILE:splatcl> batch ${BATCH_DIR}/case.json --list)
# A model whose CSM would not fit fails alone, with the cause, its splats written (the OOM killer
# ended the whole run before; SPLATCL_MEMORY_LIMIT stands in for a small machine).
file(WRITE ${BATCH_DIR}/memory.json "{\"models\": [{\"path\": \"${SPLATS_CUBE}\", \"id\": \"cube\", \"res\": 64, \"maps\": 64}]}")
add_test(NAME cli.batch_model_beyond_memory_fails_alone COMMAND sh -c
         "rm -rf \"$0/memory-out\"; SPLATCL_MEMORY_LIMIT=1M \"$1\" batch \"$0/memory.json\" -o \"$0/memory-out\" > \"$0/memory.txt\"; status=$?; cat \"$0/memory.txt\"; [ $status -eq 2 ] && grep -q '^FAILED  cube: csm: the CSM build at resolution 64 with 64 maps (its compressed maps hold .*) needs about .* more memory' \"$0/memory.txt\" && [ -s \"$0/memory-out/cube.splats.ply\" ] && [ ! -e \"$0/memory-out/cube.csm\" ]"
         ${BATCH_DIR} $<TARGET_FILE:splatcl>)
add_test(NAME cli.error_batch_missing_manifest COMMAND ${EXPECT_ERROR} "cannot read manifest .*missing.json: No such file"
         $<TARGET_FILE:splatcl> batch missing.json -o ${BATCH_DIR}/out)
add_test(NAME cli.error_batch_bad_json COMMAND ${EXPECT_ERROR} "bad.json: not valid JSON: parse error at line 1"
         $<TARGET_FILE:splatcl> batch ${BATCH_DIR}/bad.json -o ${BATCH_DIR}/out)
add_test(NAME cli.error_batch_unknown_key COMMAND ${EXPECT_ERROR} "unknown-key.json: models\\[0\\] \\(a\\): unknown parameter 'epsilon'"
         $<TARGET_FILE:splatcl> batch ${BATCH_DIR}/unknown-key.json -o ${BATCH_DIR}/out)
add_test(NAME cli.error_batch_bad_value COMMAND ${EXPECT_ERROR} "bad-value.csv:2 \\(a\\): 'k' must be an integer from 1 to 1024, got 'zero'"
         $<TARGET_FILE:splatcl> batch ${BATCH_DIR}/bad-value.csv -o ${BATCH_DIR}/out)
add_test(NAME cli.error_batch_bad_option COMMAND ${EXPECT_ERROR} "ok.csv:2 \\(a\\): 'maps': .*not a perfect square"
         $<TARGET_FILE:splatcl> batch ${BATCH_DIR}/ok.csv -o ${BATCH_DIR}/out --maps 1000)
add_test(NAME cli.error_batch_bad_shard COMMAND ${EXPECT_ERROR} "bad shard '3/3': i must be below N"
         $<TARGET_FILE:splatcl> batch ${BATCH_DIR}/ok.csv -o ${BATCH_DIR}/out --shard 3/3)
# --outputs "" is refused as "outputs": [] is (it built both outputs).
add_test(NAME cli.error_batch_empty_outputs COMMAND ${EXPECT_ERROR} "'outputs' must name at least one of splats, csm"
         $<TARGET_FILE:splatcl> batch ${BATCH_DIR}/ok.csv -o ${BATCH_DIR}/out --outputs "")
add_test(NAME cli.error_batch_no_output COMMAND ${EXPECT_ERROR} "-o OUTDIR" $<TARGET_FILE:splatcl> batch ${BATCH_DIR}/ok.csv)
add_test(NAME cli.error_batch_merge_not_summary COMMAND ${EXPECT_ERROR} "not-summary.json: not a splatcl batch summary"
         $<TARGET_FILE:splatcl> batch merge ${BATCH_DIR}/not-summary.json -o ${BATCH_DIR}/merged.json)
# -o naming one of the summaries: refused before reading (it replaced shard 0's summary).
add_test(NAME cli.error_batch_merge_over_input COMMAND ${EXPECT_ERROR} "-o .*summary-0-of-2.json would overwrite the shard summary"
         $<TARGET_FILE:splatcl> batch merge ${BATCH_DIR}/summary-0-of-2.json ${BATCH_DIR}/summary-1-of-2.json -o ${BATCH_DIR}/summary-0-of-2.json)
# -o naming a lock file (a summary folder's, live for a run elsewhere): renamed over, its locks were lost.
add_test(NAME cli.error_batch_merge_over_lock_file COMMAND ${EXPECT_ERROR} "batch merge: -o .*/.splatcl-batch.lock is a batch run's lock file$"
         $<TARGET_FILE:splatcl> batch merge ${BATCH_DIR}/summary-0-of-2.json -o ${BATCH_DIR}/elsewhere/.splatcl-batch.lock)
# Small contract slips a helper's audit found (2026-12-07): each one line naming the cause.
file(WRITE ${BATCH_DIR}/defaults-id.json "{\"defaults\": {\"id\": \"x\"}, \"models\": [\"a.obj\"]}")
add_test(NAME cli.error_batch_defaults_id COMMAND ${EXPECT_ERROR} "defaults-id.json: defaults: 'id' names one model; give it in each model's entry"
         $<TARGET_FILE:splatcl> batch ${BATCH_DIR}/defaults-id.json -o ${BATCH_DIR}/out)
add_test(NAME cli.error_batch_jobs_zero COMMAND ${EXPECT_ERROR} "--jobs 0: not a whole number 1 or more$"
         $<TARGET_FILE:splatcl> batch ${BATCH_DIR}/ok.csv -o ${BATCH_DIR}/out --jobs 0)
add_test(NAME cli.error_batch_jobs_negative COMMAND ${EXPECT_ERROR} "--jobs -1: not a whole number 1 or more"
         $<TARGET_FILE:splatcl> batch ${BATCH_DIR}/ok.csv -o ${BATCH_DIR}/out --jobs -1)
add_test(NAME cli.error_option_given_twice COMMAND ${EXPECT_ERROR} "--res given 2 times: give it once"
         $<TARGET_FILE:splatcl> batch ${BATCH_DIR}/ok.csv -o ${BATCH_DIR}/out --res 8 --res 16)
add_test(NAME cli.error_batch_missing_directory COMMAND ${EXPECT_ERROR} "cannot read manifest .*no-such-folder: No such file or directory$"
         $<TARGET_FILE:splatcl> batch ${BATCH_DIR}/no-such-folder -o ${BATCH_DIR}/out)
add_test(NAME cli.error_device_and_reference COMMAND ${EXPECT_ERROR} "--device and --reference contradict"
         $<TARGET_FILE:splatcl> batch ${BATCH_DIR}/ok.csv -o ${BATCH_DIR}/out --device nosuch --reference)
add_test(NAME cli.error_batch_outputs_twice COMMAND ${EXPECT_ERROR} "'outputs' names 'splats' twice$"
         $<TARGET_FILE:splatcl> batch ${BATCH_DIR}/ok.csv -o ${BATCH_DIR}/out --outputs splats,splats)
add_test(NAME cli.error_batch_outputs_empty_name COMMAND ${EXPECT_ERROR} "'outputs' has unknown output ''"
         $<TARGET_FILE:splatcl> batch ${BATCH_DIR}/ok.csv -o ${BATCH_DIR}/out --outputs splats,,csm)
file(WRITE ${BATCH_DIR}/outputs-trailing-plus.csv "path,outputs\na.obj,splats+\n")
add_test(NAME cli.error_batch_outputs_trailing_plus COMMAND ${EXPECT_ERROR} "'outputs' has unknown output ''"
         $<TARGET_FILE:splatcl> batch ${BATCH_DIR}/outputs-trailing-plus.csv -o ${BATCH_DIR}/out)
foreach(script resume shards failure parameters)
  add_test(NAME cli.batch_${script} COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/batch/cli_${script}_test.sh $<TARGET_FILE:splatcl>
           ${CMAKE_CURRENT_BINARY_DIR}/batch-${script})
endforeach()
# docs/batch.md's sbatch script on a single-node Slurm the test starts (slurm-wlm, munge; skipped
# with a message where the daemons cannot start). About 30 s on the 2-core VM: not in the ASan pass.
if(NOT SPLATCL_SANITIZE)
  add_test(NAME cli.batch_slurm COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/batch/cli_slurm_test.sh $<TARGET_FILE:splatcl>
           ${CMAKE_CURRENT_BINARY_DIR}/batch-slurm)
  set_tests_properties(cli.batch_slurm PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 180)
endif()
