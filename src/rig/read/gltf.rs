//! The glTF 2.0 file: its JSON and binary chunk (the GLB container read and
//! written here), its node hierarchy and world matrices, its buffers, its
//! inverse bind matrices, and what its JSON says about nodes (VRM humanoid
//! tables, skin joints). Everything format-specific that `read` needs
//! outside the mesh ([`super::skin`]) lives here.

mod precheck;

use super::anim;
use crate::dataset::DataError;
use base64::Engine;
use glam::{DMat4, DQuat, DVec3};
use precheck::precheck;
use std::path::{Path, PathBuf};

/// A glTF file, parsed, with its node hierarchy evaluated.
pub struct GltfFile {
    /// The file as the user named it.
    pub label: String,
    pub document: gltf::Document,
    /// The JSON part, for edits that must keep every field of the file.
    pub json: serde_json::Value,
    /// The binary chunk of a .glb file.
    pub blob: Option<Vec<u8>>,
    /// Each node's parent.
    pub parent: Vec<Option<usize>>,
    /// Each node's world matrix in the node pose.
    pub world: Vec<DMat4>,
    /// The folder of the file, where external buffers are read (`None` for
    /// bytes not read from a file: external buffers are then not read).
    pub dir: Option<PathBuf>,
    /// What the file was when it was FBX, read as this glTF document ([`super::fbx`]).
    pub fbx: Option<super::source::FbxSource>,
}

/// The local matrix of a node, in f64.
pub(crate) fn local_matrix(node: &gltf::Node<'_>) -> DMat4 {
    match node.transform() {
        gltf::scene::Transform::Matrix { matrix } => {
            DMat4::from_cols_array_2d(&matrix.map(|c| c.map(f64::from)))
        }
        gltf::scene::Transform::Decomposed {
            translation,
            rotation,
            scale,
        } => DMat4::from_scale_rotation_translation(
            DVec3::from_array(scale.map(f64::from)),
            DQuat::from_array(rotation.map(f64::from)).normalize(),
            DVec3::from_array(translation.map(f64::from)),
        ),
    }
}

impl GltfFile {
    /// Reads a .gltf or .glb file (external buffers are not needed to audit).
    pub fn load(path: &Path) -> Result<GltfFile, DataError> {
        let label = path.display().to_string();
        if path.is_dir() {
            return Err(DataError::whole_file(&label, directory_given(path)));
        }
        let bytes = crate::dataset::csvinput::read_input(path)?;
        let mut file = GltfFile::from_bytes(&label, &bytes)?;
        file.dir = Some(path.parent().unwrap_or(Path::new(".")).to_path_buf());
        Ok(file)
    }

    /// The data of every buffer, when all can be read: from the GLB chunk
    /// and data URIs, and from files beside it when read from a file.
    pub fn buffer_data(&self) -> Option<Vec<Vec<u8>>> {
        let external = self
            .document
            .buffers()
            .any(|b| matches!(b.source(), gltf::buffer::Source::Uri(u) if !u.starts_with("data:")));
        let dir = match (&self.dir, external) {
            (Some(d), _) => d.clone(),
            (None, false) => PathBuf::from("."),
            (None, true) => return None,
        };
        buffers(self, &dir).ok()
    }

    /// Parses the bytes of a glTF file; `label` names it in errors.
    ///
    /// The JSON is validated by the gltf crate, except `extensionsRequired`:
    /// an audit reads only nodes and skins, so a file needing, say, mesh
    /// compression is still read. Node transforms must give finite world
    /// matrices. Never panics: the inputs known to panic inside the gltf crate,
    /// or to index out of range when its data is read, are refused first
    /// (`precheck`), and any other panic there becomes an error. Every problem
    /// found at the door (this file's checks and the crate's validation) is
    /// reported in one error, each with its JSON path.
    pub fn from_bytes(label: &str, bytes: &[u8]) -> Result<GltfFile, DataError> {
        let fail = |what: String| DataError::whole_file(label, what);
        let (json_bytes, blob) = if bytes.starts_with(b"glTF") {
            split_glb(bytes).map_err(|e| fail(format!("has a broken GLB container: {e}")))?
        } else {
            (bytes, None)
        };
        let json: serde_json::Value = match serde_json::from_slice(json_bytes) {
            Ok(v) => v,
            Err(e) => {
                return Err(fail(super::sniff::not_gltf(bytes, None).unwrap_or_else(|| {
                    format!(
                        "is not a valid glTF 2.0 file (its JSON is unreadable: {e}); export it as glTF 2.0 (.glb or .gltf)"
                    )
                })));
            }
        };
        if !bytes.starts_with(b"glTF")
            && let Some(what) = super::sniff::not_gltf(bytes, Some(&json))
        {
            return Err(fail(what));
        }
        // Every problem found at the door is reported together: this file's
        // own checks (what the gltf crate would unwrap or index out of range),
        // then the gltf crate's validation, each with its JSON path.
        let mut problems = precheck(&json, blob.map(<[u8]>::len));
        let invalid = |problems: Vec<String>| DataError {
            file: label.to_string(),
            problems: problems
                .into_iter()
                .map(|e| crate::dataset::Problem::file(format!("is not valid glTF 2.0: {e}")))
                .collect(),
        };
        let mut for_document = json.clone();
        if let Some(o) = for_document.as_object_mut() {
            o.remove("extensionsRequired");
        }
        // Channels the gltf crate cannot read (a path it does not know, or
        // KHR_animation_pointer's target without a node) are left out of its
        // copy: the raw JSON keeps them, reported and untouched (see anim).
        // (`get_mut`, not indexing: indexing a missing key would add a null.)
        if let Some(list) = for_document
            .get_mut("animations")
            .and_then(serde_json::Value::as_array_mut)
        {
            for anim in list.iter_mut() {
                if let Some(chs) = anim.get_mut("channels").and_then(|c| c.as_array_mut()) {
                    chs.retain(anim::is_plain);
                }
            }
            list.retain(|a| a["channels"].as_array().is_some_and(|c| !c.is_empty()));
        }
        let root: gltf::json::Root = match serde_json::from_value(for_document) {
            Ok(root) => root,
            Err(_) if !problems.is_empty() => return Err(invalid(problems)),
            Err(e) => {
                return Err(fail(format!(
                    "is not a valid glTF 2.0 file ({e}); export it as glTF 2.0 (.glb or .gltf)"
                )));
            }
        };
        // The crate's validation panics on what `precheck` finds (a mesh
        // attribute naming a missing accessor): then its problems stand alone.
        let document = match quietly(|| gltf::Document::from_json(root)) {
            Some(Ok(document)) if problems.is_empty() => document,
            Some(Ok(_)) => return Err(invalid(problems)),
            Some(Err(gltf::Error::Validation(errors))) => {
                problems.extend(errors.iter().map(|(path, e)| validation_words(path, e)));
                return Err(invalid(problems));
            }
            Some(Err(e)) => {
                problems.push(format!("{e}; export it as glTF 2.0 (.glb or .gltf)"));
                return Err(invalid(problems));
            }
            None if !problems.is_empty() => return Err(invalid(problems)),
            None => {
                return Err(fail(
                    "could not be parsed: the glTF reader failed on it; re-export it".into(),
                ));
            }
        };
        let n = document.nodes().len();
        let mut parent = vec![None; n];
        for node in document.nodes() {
            for child in node.children() {
                if parent[child.index()].is_some() {
                    return Err(fail(format!(
                        "node {} has two parents; a glTF node hierarchy must be a forest",
                        child.index()
                    )));
                }
                parent[child.index()] = Some(node.index());
            }
        }
        let locals: Vec<DMat4> = document.nodes().map(|n| local_matrix(&n)).collect();
        let world = world_matrices(&parent, &locals).ok_or_else(|| {
            fail("has a cycle in its node hierarchy; a node cannot be its own ancestor".into())
        })?;
        Ok(GltfFile {
            label: label.to_string(),
            document,
            json,
            blob: blob.map(<[u8]>::to_vec),
            parent,
            world,
            dir: None,
            fbx: None,
        })
    }

    /// The names of all nodes (index order), unnamed ones as `#i`.
    pub fn node_names(&self) -> Vec<String> {
        self.document
            .nodes()
            .map(|n| {
                n.name()
                    .map_or_else(|| format!("#{}", n.index()), str::to_string)
            })
            .collect()
    }

    /// Node `i`'s name, `#i` when it has none (or there is no such node).
    pub fn node_name(&self, i: usize) -> String {
        self.document
            .nodes()
            .nth(i)
            .and_then(|n| n.name().map(str::to_string))
            .unwrap_or_else(|| format!("#{i}"))
    }
}

/// What to say of a directory given as a rig: the rig files it holds (the
/// first 8, by name), or that it holds none.
pub(crate) fn directory_given(dir: &Path) -> String {
    let mut rigs: Vec<String> = std::fs::read_dir(dir)
        .into_iter()
        .flatten()
        .flatten()
        .filter(|e| e.path().is_file())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| {
            let n = n.to_ascii_lowercase();
            [".glb", ".gltf", ".vrm", ".fbx"]
                .iter()
                .any(|x| n.ends_with(x))
        })
        .collect();
    rigs.sort();
    let n = rigs.len();
    match n {
        0 => {
            "is a directory, not a rig file, and holds no .glb, .gltf, .vrm or .fbx file; give the \
              path of the rig file itself"
                .to_string()
        }
        _ => {
            let shown: Vec<String> = rigs
                .iter()
                .take(8)
                .map(|r| dir.join(r).display().to_string())
                .collect();
            format!(
                "is a directory, not a rig file; it holds {n} rig file{}: {}{}; give one of them",
                if n == 1 { "" } else { "s" },
                shown.join(", "),
                if n > 8 { ", ..." } else { "" }
            )
        }
    }
}

/// Decodes `%xx` escapes of a URI path; `None` on a bad escape or non-UTF-8 result.
fn percent_decode(uri: &str) -> Option<String> {
    let b = uri.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hex = std::str::from_utf8(b.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

/// Reads the data of every buffer: the GLB chunk (buffer 0 only, as the
/// specification says), data URIs, or files beside the input. A file URI must
/// be a relative path that stays beside the input (no `..`, no scheme), and
/// only the declared byte length is read.
pub(crate) fn buffers(file: &GltfFile, dir: &Path) -> Result<Vec<Vec<u8>>, DataError> {
    let fail = |m: String| DataError::whole_file(&file.label, m);
    file.document
        .buffers()
        .map(|b| {
            let i = b.index();
            let mut data = match b.source() {
                gltf::buffer::Source::Bin if i == 0 => file
                    .blob
                    .clone()
                    .ok_or_else(|| fail("refers to a GLB binary chunk it does not have".into()))?,
                gltf::buffer::Source::Bin => {
                    return Err(fail(format!(
                        "buffer {i} has no data of its own (a compression fallback buffer?); --fix cannot copy it"
                    )));
                }
                gltf::buffer::Source::Uri(uri) => {
                    if let Some(rest) = uri.strip_prefix("data:") {
                        let payload = rest
                            .split_once(";base64,")
                            .map(|(_, p)| p)
                            .ok_or_else(|| fail(format!("buffer {i} has a data URI that is not base64")))?;
                        base64::engine::general_purpose::STANDARD
                            .decode(payload)
                            .map_err(|e| fail(format!("buffer {i} has bad base64 ({e})")))?
                    } else {
                        let rel = percent_decode(uri)
                            .filter(|r| {
                                let p = Path::new(r);
                                !r.contains(':')
                                    && p.is_relative()
                                    && p.components().all(|c| matches!(c, std::path::Component::Normal(_)))
                            })
                            .ok_or_else(|| {
                                fail(format!(
                                    "buffer {i} refers to '{uri}', which is not a plain relative path beside the file; \
                                     --fix reads only files next to the input"
                                ))
                            })?;
                        let p = dir.join(rel);
                        let read = || -> std::io::Result<Vec<u8>> {
                            let mut data = Vec::new();
                            std::io::Read::read_to_end(
                                &mut std::io::Read::take(std::fs::File::open(&p)?, (b.length() as u64).saturating_add(1)),
                                &mut data,
                            )?;
                            Ok(data)
                        };
                        read().map_err(|e| {
                            fail(format!(
                                "buffer {i} refers to {} which cannot be read ({e}); keep it beside the .gltf",
                                p.display()
                            ))
                        })?
                    }
                }
            };
            if data.len() < b.length() {
                return Err(fail(format!(
                    "buffer {i} holds {} bytes but declares {}",
                    data.len(),
                    b.length()
                )));
            }
            data.truncate(b.length());
            Ok(data)
        })
        .collect()
}

/// The inverse bind matrices of a skin, read with every offset checked
/// (identity matrices when the skin has none).
pub(crate) fn inverse_binds(
    data: &[Vec<u8>],
    skin: &gltf::Skin<'_>,
    joints: usize,
) -> Result<Vec<DMat4>, String> {
    let Some(acc) = skin.inverse_bind_matrices() else {
        return Ok(vec![DMat4::IDENTITY; joints]);
    };
    let what = format!(
        "skin {}'s inverse bind matrices (accessor {})",
        skin.index(),
        acc.index()
    );
    if acc.data_type() != gltf::accessor::DataType::F32
        || acc.dimensions() != gltf::accessor::Dimensions::Mat4
        || acc.sparse().is_some()
        || acc.count() != joints
    {
        return Err(format!(
            "{what} are not {joints} plain float MAT4 values, as glTF requires"
        ));
    }
    let view = acc
        .view()
        .ok_or_else(|| format!("{what} have no buffer view"))?;
    let stride = view.stride().unwrap_or(64);
    let buf = data
        .get(view.buffer().index())
        .ok_or_else(|| format!("{what} name a missing buffer"))?;
    let start = view.offset().checked_add(acc.offset());
    let need = stride
        .checked_mul(joints.saturating_sub(1))
        .and_then(|x| x.checked_add(64));
    let in_view = need.and_then(|n| acc.offset().checked_add(n));
    let view_end = view.offset().checked_add(view.length());
    let (Some(start), Some(in_view), Some(view_end)) = (start, in_view, view_end) else {
        return Err(format!("{what} have impossible offsets"));
    };
    if stride < 64 || in_view > view.length() || view_end > buf.len() {
        return Err(format!("{what} do not fit their buffer view"));
    }
    Ok((0..joints)
        .map(|k| {
            let at = start + k * stride;
            let cols: Vec<f64> = buf[at..at + 64]
                .chunks_exact(4)
                .map(|c| f64::from(f32::from_le_bytes([c[0], c[1], c[2], c[3]])))
                .collect();
            DMat4::from_cols_slice(&cols)
        })
        .collect())
}

/// The JSON and binary chunks of a GLB file, with every length checked.
fn split_glb(bytes: &[u8]) -> Result<(&[u8], Option<&[u8]>), String> {
    let word = |at: usize| -> Option<u32> {
        bytes
            .get(at..at.checked_add(4)?)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    };
    let version = word(4).ok_or("the header is cut short")?;
    if version != 2 {
        return Err(format!("version {version}; only glTF 2.0 is read"));
    }
    let total = word(8).ok_or("the header is cut short")? as usize;
    if total < 20 || total > bytes.len() {
        return Err(format!("it declares {total} bytes but has {}", bytes.len()));
    }
    let mut chunks = Vec::new();
    let mut at = 12usize;
    while at < total {
        let len = word(at).ok_or("a chunk header is cut short")? as usize;
        let kind = word(at + 4).ok_or("a chunk header is cut short")?;
        let start = at + 8;
        let end = start
            .checked_add(len)
            .filter(|&e| e <= total)
            .ok_or("a chunk runs past the end")?;
        chunks.push((kind, &bytes[start..end]));
        at = end;
    }
    match chunks.as_slice() {
        [(0x4E4F_534A, json), rest @ ..] => {
            let bin = rest
                .iter()
                .find(|(k, _)| *k == 0x004E_4942)
                .map(|(_, b)| *b);
            Ok((json, bin))
        }
        _ => Err("its first chunk is not JSON".into()),
    }
}

/// One problem of the gltf crate's validation, its path as a JSON pointer
/// (`accessors[0].bufferView` as `/accessors/0/bufferView`, as [`precheck`]
/// names them) and what it means.
fn validation_words(path: &gltf::json::Path, e: &gltf::json::validation::Error) -> String {
    use gltf::json::validation::Error as E;
    let pointer: String = path
        .to_string()
        .replace('[', ".")
        .replace(']', "")
        .split('.')
        .filter(|p| !p.is_empty())
        .map(|p| format!("/{p}"))
        .collect();
    let what = match e {
        E::IndexOutOfBounds => "names an entry that does not exist (index out of range)",
        E::Invalid => "has a value glTF 2.0 does not allow",
        E::Missing => "is missing, and glTF 2.0 requires it",
        E::Oversize => "is too large to read",
        E::Unsupported => "needs an extension this reader does not support",
    };
    format!("{pointer} {what}")
}

/// `json` and `bin` as the bytes of a GLB file (the binary chunk left out when `bin` is
/// empty); the error says what could not be written. Cost: O(bytes).
pub(crate) fn glb(json: &serde_json::Value, bin: Vec<u8>) -> Result<Vec<u8>, String> {
    let text = serde_json::to_vec(json).map_err(|e| e.to_string())?;
    gltf::binary::Glb {
        header: gltf::binary::Header {
            magic: *b"glTF",
            version: 2,
            length: 0,
        },
        json: text.into(),
        bin: (!bin.is_empty()).then_some(bin.into()),
    }
    .to_vec()
    .map_err(|e| format!("cannot be written as GLB ({e})"))
}

thread_local! {
    static QUIET: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Runs `f`, turning a panic into `None` without printing it. One panic hook,
/// installed once, stays silent while its thread is inside `quietly` and
/// otherwise passes on to the hook that was there before, so concurrent
/// callers cannot leave the process with a silent hook.
fn quietly<T>(f: impl FnOnce() -> T) -> Option<T> {
    static INSTALL: std::sync::Once = std::sync::Once::new();
    INSTALL.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !QUIET.with(std::cell::Cell::get) {
                previous(info);
            }
        }));
    });
    QUIET.with(|q| q.set(true));
    let out = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).ok();
    QUIET.with(|q| q.set(false));
    out
}

/// World matrices from parents and local matrices; `None` on a cycle. O(n depth).
pub(crate) fn world_matrices(parent: &[Option<usize>], locals: &[DMat4]) -> Option<Vec<DMat4>> {
    let n = locals.len();
    let mut world: Vec<Option<DMat4>> = vec![None; n];
    for start in 0..n {
        let mut path = vec![start];
        while let Some(p) = parent[*path.last()?] {
            if world[p].is_some() {
                break;
            }
            if path.len() > n {
                return None;
            }
            path.push(p);
        }
        for &i in path.iter().rev() {
            if world[i].is_none() {
                let up = parent[i].map_or(DMat4::IDENTITY, |p| world[p].unwrap_or(DMat4::IDENTITY));
                world[i] = Some(up * locals[i]);
            }
        }
    }
    world.into_iter().collect()
}

/// VRM humanoid bones (0.x `extensions.VRM`, 1.0 `extensions.VRMC_vrm`) as (node, bone name, 0.x?).
pub(crate) fn vrm_bones(json: &serde_json::Value) -> Vec<(usize, String, bool)> {
    let mut out = Vec::new();
    let ext = &json["extensions"];
    if let Some(bones) = ext["VRMC_vrm"]["humanoid"]["humanBones"].as_object() {
        for (name, b) in bones {
            if let Some(node) = b["node"].as_u64() {
                out.push((node as usize, name.clone(), false));
            }
        }
    }
    if let Some(bones) = ext["VRM"]["humanoid"]["humanBones"].as_array() {
        for b in bones {
            if let (Some(name), Some(node)) = (b["bone"].as_str(), b["node"].as_u64()) {
                out.push((node as usize, name.to_string(), true));
            }
        }
    }
    out
}

/// Which nodes may be finger joints (the joints of any skin and everything
/// below them; every node of a file without skins), and which are skinned. O(n).
pub(crate) fn candidates(file: &GltfFile) -> (Vec<bool>, Vec<bool>) {
    let n = file.parent.len();
    let mut candidate = vec![false; n];
    let mut skinned = vec![false; n];
    let skins: Vec<_> = file.document.skins().collect();
    for skin in &skins {
        for j in skin.joints() {
            skinned[j.index()] = true;
        }
    }
    if skins.is_empty() {
        candidate.fill(true);
    } else {
        // Skinned joints and everything below them, each node visited once.
        let mut children = vec![Vec::new(); n];
        for (i, p) in file.parent.iter().enumerate() {
            if let Some(p) = *p {
                children[p].push(i);
            }
        }
        let mut stack: Vec<usize> = (0..n).filter(|&i| skinned[i]).collect();
        while let Some(i) = stack.pop() {
            if !std::mem::replace(&mut candidate[i], true) {
                stack.extend_from_slice(&children[i]);
            }
        }
    }
    (candidate, skinned)
}
