//! A seeded mutation loop over the `make` fuzz target's body
//! (fuzz/fuzz_targets/make.rs), for machines without cargo-fuzz: every
//! shared rig (../shared/rigs, skipped with the reason when absent; a glTF
//! with its buffer in a file or a data URI packed into one GLB, as the
//! fuzz corpus holds it) with flipped bits, cut tails, spliced runs,
//! numbers of its JSON tweaked, members of its JSON removed and words of
//! its binary chunk overwritten with NaN, infinities, zeros, huge floats and
//! huge indices. Each mutant is read, made (`make::make`, without and with
//! `--replace-fingers`) and the copy read back and audited, as
//! `session::rig` does before it writes: it is made or refused, never a
//! panic. The mutations are the same on every machine (ChaCha8, fixed seeds).

use crate::common::{glb, manifest_dir, paper_data, shared_rig_files};
use phalanx::analysis::{Analysis, Settings, analyse_without_bootstrap};
use phalanx::dataset::{Dataset, SummaryTable};
use phalanx::rig::judge::SoftTissue;
use phalanx::rig::make::names::Names;
use phalanx::rig::make::place::Proportions;
use phalanx::rig::make::write::WriteOptions;
use phalanx::rig::make::{MakeOptions, make};
use phalanx::rig::naming::Side;
use phalanx::rig::{AuditOptions, AuditedRig, GltfFile, Rig, session};
use rand_chacha::ChaCha8Rng;
use rand_core::{Rng, SeedableRng};
use serde_json::Value;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;
use std::time::Instant;

/// The paper's analysis and the proportions `rig` places joints from, as
/// the fuzz target makes them (the atlas's when data/atlas is there).
fn proportions() -> (Analysis, Proportions) {
    let settings = Settings::default();
    let d = Dataset::from_bytes("measurements.csv", &paper_data()).unwrap();
    let a = analyse_without_bootstrap(&d, &settings);
    let path = manifest_dir().join("data/atlas/measurements.csv");
    let atlas = Dataset::load(&path)
        .ok()
        .map(|d| analyse_without_bootstrap(&d, &settings));
    let wrist = session::wrist_ratios_beside(&path).ok().flatten();
    let soft = SummaryTable::load(&manifest_dir().join("data/literature/buryanov-kotiuk-2010.csv"))
        .map(|t| SoftTissue::from_table(&t, None))
        .unwrap_or(SoftTissue::Unknown);
    let p = Proportions::new(&a, atlas.as_ref(), wrist.as_ref(), soft);
    (a, p)
}

/// How far an input went: read as a rig, made (either way), its copy read back.
#[derive(Debug, Default, Clone, Copy)]
struct Reached {
    read: bool,
    made: bool,
    read_back: bool,
}

/// The fuzz target's body (fuzz/fuzz_targets/make.rs): the input read as
/// `read::open` reads it (FBX by its header), made as `knob` chooses (the
/// target's is the input's last byte), without and with `--replace-fingers`,
/// and each copy read back and audited.
fn make_path(a: &Analysis, p: &Proportions, data: &[u8], knob: u8) -> Reached {
    let mut reached = Reached::default();
    let file = if phalanx::rig::fbx::is_fbx(Path::new("fuzz.glb"), data) {
        phalanx::rig::fbx::read("fuzz.fbx", data)
    } else {
        GltfFile::from_bytes("fuzz.glb", data)
    };
    let Ok(file) = file else {
        return reached;
    };
    let Ok(rig) = Rig::from_file(file, None) else {
        return reached;
    };
    reached.read = true;
    let side = match knob % 3 {
        0 => None,
        1 => Some(Side::Left),
        _ => Some(Side::Right),
    };
    let fingers = match (knob / 3) % 4 {
        0 => None,
        k => Some(k as usize + 2),
    };
    let names = [
        Names::Openxr,
        Names::Vrm,
        Names::Mixamo,
        Names::Unreal,
        Names::Rigify,
    ][usize::from(knob / 12) % 5];
    let wrist = (knob >= 128)
        .then(|| rig.file.world.first().map(|m| m.w_axis.truncate()))
        .flatten();
    for replace_fingers in [false, true] {
        let opts = MakeOptions {
            side,
            wrist,
            fingers,
            write: WriteOptions {
                names,
                replace_fingers,
                glb: knob & 1 == 0,
            },
        };
        let Ok(made) = make(&rig, p, &opts, Path::new("/nonexistent-phalanx-fuzz")) else {
            continue;
        };
        reached.made = true;
        for f in &made.hand.fingers {
            assert!(f.joints.iter().all(|(_, at)| at.is_finite()), "{f:?}");
        }
        let Ok(copy) = GltfFile::from_bytes("rigged.glb", &made.written.bytes) else {
            continue;
        };
        let Ok(again) = Rig::from_file(copy, None) else {
            continue;
        };
        reached.read_back = true;
        let chains: Vec<_> = again
            .chains
            .iter()
            .filter(|c| c.side.is_none_or(|s| s == made.hand.side))
            .cloned()
            .collect();
        let _ = AuditedRig::with(
            "rigged.glb",
            &chains,
            &again.notes,
            a,
            &AuditOptions::default(),
            again.weights.as_ref(),
        );
    }
    reached
}

/// The JSON chunk's range and the binary chunk's range of a GLB, when its
/// chunk headers are whole.
fn chunks(bytes: &[u8]) -> Option<(std::ops::Range<usize>, Option<std::ops::Range<usize>>)> {
    let word = |at: usize| -> Option<usize> {
        Some(u32::from_le_bytes(bytes.get(at..at + 4)?.try_into().ok()?) as usize)
    };
    if !bytes.starts_with(b"glTF") {
        return None;
    }
    let len = word(12)?;
    let json = 20..(20 + len).min(bytes.len());
    let at = 20 + len;
    let bin = word(at)
        .map(|n| (at + 8).min(bytes.len())..(at + 8 + n).min(bytes.len()))
        .filter(|r| !r.is_empty());
    Some((json, bin))
}

/// A shared rig as one input: a GLB or FBX as it is, a .gltf with its one
/// buffer (a file beside it or a data URI) packed into a GLB.
fn one_input(path: &Path) -> Vec<u8> {
    let bytes = std::fs::read(path).unwrap();
    if path.extension().and_then(|e| e.to_str()) != Some("gltf") {
        return bytes;
    }
    let mut doc: Value = serde_json::from_slice(&bytes).unwrap();
    let buffers = doc["buffers"].as_array().map_or(0, Vec::len);
    let Some(uri) = doc["buffers"][0]["uri"].as_str().filter(|_| buffers == 1) else {
        return bytes;
    };
    let bin = match uri.split_once(";base64,") {
        Some((_, b64)) => {
            use base64::Engine;
            base64::engine::general_purpose::STANDARD
                .decode(b64)
                .unwrap()
        }
        None => std::fs::read(path.with_file_name(uri)).unwrap(),
    };
    doc["buffers"][0].as_object_mut().unwrap().remove("uri");
    glb(&doc, &bin)
}

fn below(rng: &mut ChaCha8Rng, n: usize) -> usize {
    (rng.next_u64() % n.max(1) as u64) as usize
}

/// Every number of `v`, as mutable references.
fn numbers<'a>(v: &'a mut Value, out: &mut Vec<&'a mut Value>) {
    match v {
        Value::Number(_) => out.push(v),
        Value::Array(a) => a.iter_mut().for_each(|x| numbers(x, out)),
        Value::Object(o) => o.values_mut().for_each(|x| numbers(x, out)),
        _ => {}
    }
}

/// The JSON pointer of every non-empty object of `v` (`at` its own).
fn objects(v: &Value, at: String, out: &mut Vec<String>) {
    match v {
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                objects(x, format!("{at}/{i}"), out);
            }
        }
        Value::Object(o) => {
            for (k, x) in o {
                objects(
                    x,
                    format!("{at}/{}", k.replace('~', "~0").replace('/', "~1")),
                    out,
                );
            }
            if !o.is_empty() {
                out.push(at);
            }
        }
        _ => {}
    }
}

/// One mutant of `seed`: its JSON (of a GLB or a .gltf) tweaked, or its
/// bytes changed.
fn mutate(rng: &mut ChaCha8Rng, seed: &[u8]) -> Vec<u8> {
    let mut b = seed.to_vec();
    let glb_parts = chunks(seed);
    let json_part: Option<(Value, Vec<u8>)> = match &glb_parts {
        Some((j, bin)) => serde_json::from_slice(&seed[j.clone()])
            .ok()
            .map(|v| (v, bin.clone().map_or(Vec::new(), |r| seed[r].to_vec()))),
        None => None,
    };
    match below(rng, 8) {
        // Bits flipped anywhere.
        0 => {
            for _ in 0..1 + below(rng, 16) {
                let i = below(rng, b.len());
                b[i] ^= 1 << below(rng, 8);
            }
        }
        // The tail cut.
        1 => b.truncate(below(rng, b.len())),
        // A run of the file copied elsewhere into it.
        2 => {
            let (i, j, len) = (below(rng, b.len()), below(rng, b.len()), 1 + below(rng, 64));
            let run: Vec<u8> = b[j..(j + len).min(b.len())].to_vec();
            b.splice(i..i, run);
        }
        // Words of the binary chunk (the whole file for FBX) overwritten:
        // positions, weights, indices, matrices gone wrong.
        3 | 4 => {
            let range = glb_parts
                .as_ref()
                .and_then(|(_, bin)| bin.clone())
                .unwrap_or(0..b.len());
            let words = range.len() / 4;
            const WORDS: [u32; 10] = [
                0x7FC0_0000, // NaN
                0x7F80_0000, // +inf
                0xFF80_0000, // -inf
                0,
                0x7149_F2CA, // 1e30
                0xF149_F2CA, // -1e30
                0x0000_0001, // the smallest subnormal
                0xFFFF_FFFF, // an index or a count far out
                0x0001_0000, // a 16-bit index far out (low half 0)
                0x3F80_0000, // 1.0
            ];
            for _ in 0..1 + below(rng, 8) {
                let w = range.start + 4 * below(rng, words);
                if w + 4 <= b.len() {
                    b[w..w + 4].copy_from_slice(&WORDS[below(rng, WORDS.len())].to_le_bytes());
                }
            }
        }
        // Numbers of the JSON tweaked: counts, offsets, indices, transforms.
        5 | 6 if json_part.is_some() => {
            let (mut doc, bin) = json_part.unwrap();
            let mut leaves = Vec::new();
            numbers(&mut doc, &mut leaves);
            for _ in 0..1 + below(rng, 4) {
                if leaves.is_empty() {
                    break;
                }
                let k = below(rng, leaves.len());
                let n = leaves[k].as_f64().unwrap_or(0.0);
                let new = match below(rng, 10) {
                    0 => serde_json::json!(0),
                    1 => serde_json::json!(-1),
                    2 => serde_json::json!(n + 1.0),
                    3 => serde_json::json!(n - 1.0),
                    4 => serde_json::json!(n * 1000.0),
                    5 => serde_json::json!(-n),
                    6 => serde_json::json!(1e30),
                    7 => serde_json::json!(1e-30),
                    8 => serde_json::json!(u32::MAX),
                    _ => serde_json::json!(9_007_199_254_740_993u64),
                };
                *leaves[k] = new;
            }
            return glb(&doc, &bin);
        }
        // A member of an object of the JSON removed.
        _ if json_part.is_some() => {
            let (mut doc, bin) = json_part.unwrap();
            let mut all = Vec::new();
            objects(&doc, String::new(), &mut all);
            if !all.is_empty() {
                let at = &all[below(rng, all.len())];
                let o = doc.pointer_mut(at).and_then(Value::as_object_mut).unwrap();
                let key = o.keys().nth(below(rng, o.len())).unwrap().clone();
                o.remove(&key);
            }
            return glb(&doc, &bin);
        }
        // FBX: a byte set to 0xff in a short run.
        _ => {
            let i = below(rng, b.len());
            let end = (i + 1 + below(rng, 8)).min(b.len());
            b[i..end].fill(0xff);
        }
    }
    b
}

/// The inputs mutated: every shared rig as one input ([`one_input`]), and
/// each FBX rig also as the glTF document phalanx reads it as (its geometry
/// mutated past the FBX reader, whose own fuzz target is `fbx`).
fn seeds() -> Option<Vec<(String, Vec<u8>)>> {
    let rigs = shared_rig_files()?;
    let mut seeds = Vec::new();
    for path in &rigs {
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let bytes = one_input(path);
        if phalanx::rig::fbx::is_fbx(path, &bytes) {
            let file = phalanx::rig::fbx::read(&name, &bytes).unwrap();
            let doc = glb(&file.json, file.blob.as_deref().unwrap_or_default());
            seeds.push((format!("{name} as glTF"), doc));
        }
        seeds.push((name, bytes));
    }
    Some(seeds)
}

/// Mutant `k` of seed `r`, and the options it is made with: each drawn from
/// its own ChaCha8 stream, so any one can be made again alone.
fn mutant(seed: &[u8], r: usize, k: usize) -> (Vec<u8>, u8) {
    let mut rng = ChaCha8Rng::seed_from_u64(((r as u64) << 32) | k as u64);
    let knob = rng.next_u32() as u8;
    (mutate(&mut rng, seed), knob)
}

/// Runs `per_rig` mutants of every seed through [`make_path`] (on every
/// core, catching panics), and fails naming every mutant that panicked,
/// each kept in the system's temporary folder to be run again.
fn mutants_never_panic(per_rig: usize) {
    use rayon::prelude::*;
    let Some(seeds) = seeds() else {
        return;
    };
    let (a, p) = proportions();
    let started = Instant::now();
    let runs: Vec<(usize, usize)> = (0..seeds.len())
        .flat_map(|r| (0..per_rig).map(move |k| (r, k)))
        .collect();
    let outcomes: Vec<Result<Reached, String>> = runs
        .par_iter()
        .map(|&(r, k)| {
            let (name, seed) = &seeds[r];
            let (data, knob) = mutant(seed, r, k);
            catch_unwind(AssertUnwindSafe(|| make_path(&a, &p, &data, knob))).map_err(|e| {
                let why = e
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| e.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_default();
                let kept = std::env::temp_dir().join(format!("phalanx-make-panic-{r}-{k}-{knob}"));
                let _ = std::fs::write(&kept, &data);
                format!(
                    "{name}: mutant {k} (seed {r}, knob {knob}, kept as {}): {why}",
                    kept.display()
                )
            })
        })
        .collect();
    let mut lines = Vec::new();
    for (r, (name, _)) in seeds.iter().enumerate() {
        let mine = &outcomes[r * per_rig..(r + 1) * per_rig];
        let count = |f: fn(&Reached) -> bool| mine.iter().flatten().filter(|x| f(x)).count();
        lines.push(format!(
            "{name}: {per_rig} mutants, {} read, {} made, {} read back",
            count(|x| x.read),
            count(|x| x.made),
            count(|x| x.read_back)
        ));
    }
    eprintln!(
        "{}\n{} mutants of {} inputs in {:.1} s",
        lines.join("\n"),
        runs.len(),
        seeds.len(),
        started.elapsed().as_secs_f64()
    );
    let panics: Vec<&String> = outcomes.iter().filter_map(|o| o.as_ref().err()).collect();
    assert!(
        panics.is_empty(),
        "{} panics:\n{}",
        panics.len(),
        panics
            .iter()
            .map(|s| s.as_str())
            .collect::<Vec<_>>()
            .join("\n")
    );
}

#[test]
fn mutated_rigs_are_made_or_refused_never_a_panic() {
    mutants_never_panic(6);
}

#[test]
#[ignore = "slow: 200 mutants of every shared rig, about a second each when made in the debug build (run with --ignored, best with --release)"]
fn two_hundred_mutants_of_every_shared_rig_are_made_or_refused_never_a_panic() {
    mutants_never_panic(200);
}
