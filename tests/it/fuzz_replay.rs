//! Replays the fuzz corpora (`fuzz/corpus/NAME/`: the seeds of `scripts/fuzz_seeds.sh` and
//! every input a fuzzing run found that once failed) through the same target code the
//! fuzzer runs (`fuzz/targets.rs`), on the stable toolchain: a reader that panics on one of
//! them fails this test. See docs/robustness.md for the fuzzing runs.

#[path = "../../fuzz/targets.rs"]
mod targets;

use std::path::Path;

#[test]
fn every_corpus_input_is_read_without_a_panic() {
    let corpus = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/corpus");
    let mut total = 0;
    for &(name, target) in targets::TARGETS {
        let n = targets::replay(&corpus, name, target);
        assert!(n > 0, "fuzz/corpus/{name} holds no input");
        total += n;
    }
    assert!(total >= targets::TARGETS.len());
}

#[test]
fn every_fuzz_target_has_a_binary() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/fuzz_targets");
    for &(name, _) in targets::TARGETS {
        assert!(
            dir.join(format!("{name}.rs")).is_file(),
            "fuzz/fuzz_targets/{name}.rs is missing"
        );
    }
}
