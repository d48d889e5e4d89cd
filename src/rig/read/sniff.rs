//! What a file that is not glTF really is, from its first bytes: an image, an
//! archive, another 3D format, a glTF 1.0 file, text. Named in the error so
//! the user knows what they gave (a PNG renamed `.glb` is no broken glTF).

/// The kind of file `bytes` begin like, with what to do, when it is a
/// recognisable non-glTF file; `None` for anything else (JSON text included).
/// O(1) but for the text check, which reads the first 512 bytes.
pub fn not_gltf(bytes: &[u8], json: Option<&serde_json::Value>) -> Option<String> {
    let starts = |magic: &[u8]| bytes.starts_with(magic);
    let what: &str = if bytes.is_empty() {
        "is empty (0 bytes)"
    } else if starts(b"\x89PNG\r\n\x1a\n") {
        "is a PNG image, not a glTF file"
    } else if starts(b"\xFF\xD8\xFF") {
        "is a JPEG image, not a glTF file"
    } else if starts(b"GIF87a") || starts(b"GIF89a") {
        "is a GIF image, not a glTF file"
    } else if starts(b"RIFF") && bytes.get(8..12) == Some(b"WEBP") {
        "is a WebP image, not a glTF file"
    } else if starts(b"%PDF") {
        "is a PDF document, not a glTF file"
    } else if starts(b"PK\x03\x04") {
        "is a ZIP archive (a zipped download?), not a glTF file; unzip it and give the .glb, .gltf or .vrm inside"
    } else if starts(b"\x1F\x8B") {
        "is gzip-compressed; decompress it and give the .glb, .gltf or .vrm inside"
    } else if starts(b"Kaydara FBX Binary") || starts(b"; FBX") {
        "is an FBX file, not glTF; export the rig as glTF 2.0 (.glb) from your 3D tool, or convert it (FBX2glTF)"
    } else if starts(b"BLENDER") {
        "is a Blender file (.blend), not glTF; in Blender use File > Export > glTF 2.0 (.glb)"
    } else if let Some(v) = json {
        return json_not_gltf(v);
    } else if looks_like_obj(bytes) {
        "is a Wavefront OBJ file, not glTF (OBJ has no skeleton to audit); export the rigged model as glTF 2.0 (.glb)"
    } else {
        return None;
    };
    let fix = if what.contains(';') || what.starts_with("is empty") {
        String::new()
    } else {
        "; give a .glb, .gltf or .vrm (glTF 2.0) file".to_string()
    };
    Some(format!("{what}{fix}"))
}

/// JSON that is not glTF 2.0: glTF 1.0 (its `asset.version`), or no glTF at all.
fn json_not_gltf(v: &serde_json::Value) -> Option<String> {
    let version = v["asset"]["version"].as_str();
    match version {
        Some(ver) if ver.starts_with('1') => Some(format!(
            "is a glTF {ver} file; only glTF 2.0 is read: convert it (for example with the Khronos \
             glTF-Pipeline or Blender's importer, then export glTF 2.0)"
        )),
        Some(_) => None,
        None if !v.is_object() => Some(
            "is JSON but not a glTF document (it is not a JSON object); give a .glb, .gltf or .vrm \
             (glTF 2.0) file"
                .into(),
        ),
        None => Some(
            "is JSON but not a glTF document (it has no \"asset\": {\"version\": \"2.0\"}); give a \
             .glb, .gltf or .vrm (glTF 2.0) file"
                .into(),
        ),
    }
}

/// True when the first lines read like a Wavefront OBJ file (`v x y z` or `o name`
/// lines, `#` comments, `mtllib`).
fn looks_like_obj(bytes: &[u8]) -> bool {
    let head = &bytes[..bytes.len().min(512)];
    let Ok(text) = std::str::from_utf8(head) else {
        return false;
    };
    let mut lines = text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'));
    lines.next().is_some_and(|l| {
        l.starts_with("v ")
            || l.starts_with("o ")
            || l.starts_with("mtllib ")
            || l.starts_with("g ")
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn files_that_are_not_gltf_are_named() {
        let png = b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR";
        let said = not_gltf(png, None).unwrap();
        assert!(
            said.starts_with("is a PNG image, not a glTF file; give a .glb"),
            "{said}"
        );
        assert!(
            not_gltf(b"\xFF\xD8\xFF\xE0", None)
                .unwrap()
                .contains("JPEG")
        );
        assert!(
            not_gltf(b"PK\x03\x04rest", None)
                .unwrap()
                .contains("unzip it")
        );
        assert!(
            not_gltf(b"Kaydara FBX Binary  \0", None)
                .unwrap()
                .contains("FBX")
        );
        assert!(
            not_gltf(b"BLENDER-v300", None)
                .unwrap()
                .contains("File > Export")
        );
        assert!(not_gltf(b"", None).unwrap().contains("empty"));
        assert!(
            not_gltf(b"# Blender\nmtllib a.mtl\no Cube\nv 1 1 1\n", None)
                .unwrap()
                .contains("OBJ")
        );
        let v1 = serde_json::json!({"asset": {"version": "1.0"}});
        assert!(not_gltf(b"{", Some(&v1)).unwrap().contains("glTF 1.0"));
        let other = serde_json::json!({"name": "x"});
        assert!(
            not_gltf(b"{", Some(&other))
                .unwrap()
                .contains("not a glTF document")
        );
        let v2 = serde_json::json!({"asset": {"version": "2.0"}});
        assert_eq!(not_gltf(b"{", Some(&v2)), None);
        assert_eq!(not_gltf(b"hello there", None), None);
    }
}
