//! The checks made before the gltf crate sees a file: what is known to
//! panic inside it, or to index out of range when the file's data is read.

/// Bytes of one component of an accessor's `componentType`; `None` for an
/// unknown type (the gltf crate's validation names it).
fn component_bytes(t: &serde_json::Value) -> Option<u64> {
    match t.as_u64()? {
        5120 | 5121 => Some(1),
        5122 | 5123 => Some(2),
        5125 | 5126 => Some(4),
        _ => None,
    }
}

/// Bytes of one element of an accessor: its components, with each matrix
/// column padded to 4 bytes as glTF 2.0 lays them out; `None` for an unknown
/// `type`.
fn element_bytes(ty: &serde_json::Value, component: u64) -> Option<u64> {
    let (columns, rows) = match ty.as_str()? {
        "SCALAR" => (1, 1),
        "VEC2" => (1, 2),
        "VEC3" => (1, 3),
        "VEC4" => (1, 4),
        "MAT2" => (2, 2),
        "MAT3" => (3, 3),
        "MAT4" => (4, 4),
        _ => return None,
    };
    let column = rows * component;
    Some(if columns == 1 {
        column
    } else {
        columns * column.div_ceil(4) * 4
    })
}

/// What is known to panic inside the gltf crate, or to index out of range
/// when the file's data is read, each with its JSON path: a mesh attribute
/// naming an accessor that does not exist (its validation indexes it); an
/// image with neither `uri` nor `bufferView`, with both, or with a
/// `bufferView` and no `mimeType` (`Image::source` unwraps them; the glTF 2.0
/// specification requires exactly one source, and the MIME type with a buffer
/// view); a GLB buffer longer than the binary chunk (`blob`, its length) that
/// holds it; and buffer views, accessors and sparse accessors whose bytes run
/// past the view or buffer they lie in. Indices out of range (a texture's
/// sampler or image, an accessor's buffer view) are left to the gltf crate's
/// validation, which names them without panicking. Every problem is listed.
/// O(JSON size).
pub(super) fn precheck(json: &serde_json::Value, blob: Option<usize>) -> Vec<String> {
    let mut problems = Vec::new();
    check_attributes(json, &mut problems);
    check_buffers(json, blob, &mut problems);
    check_accessors(json, &mut problems);
    check_images(json, &mut problems);
    problems
}

/// [`precheck`]: each mesh attribute (of a primitive or a morph target)
/// names an accessor that exists.
fn check_attributes(json: &serde_json::Value, problems: &mut Vec<String>) {
    let accessors = json["accessors"].as_array().map_or(0, Vec::len);
    for (m, mesh) in json["meshes"].as_array().into_iter().flatten().enumerate() {
        for (p, prim) in mesh["primitives"]
            .as_array()
            .into_iter()
            .flatten()
            .enumerate()
        {
            let targets = prim["targets"].as_array().into_iter().flatten();
            for attrs in std::iter::once(&prim["attributes"]).chain(targets) {
                for (name, v) in attrs.as_object().into_iter().flatten() {
                    if v.as_u64().is_none_or(|i| i >= accessors as u64) {
                        problems.push(format!(
                            "/meshes/{m}/primitives/{p}: attribute {name} names accessor {v}, which does not exist"
                        ));
                    }
                }
            }
        }
    }
}

/// [`precheck`]: a GLB's buffer within its binary chunk (`blob`), and each
/// buffer view within its buffer.
fn check_buffers(json: &serde_json::Value, blob: Option<usize>, problems: &mut Vec<String>) {
    let buffers: Vec<Option<u64>> = json["buffers"]
        .as_array()
        .into_iter()
        .flatten()
        .map(|b| b["byteLength"].as_u64())
        .collect();
    if let (Some(have), Some(Some(declared))) = (blob, buffers.first())
        && json["buffers"][0]
            .get("uri")
            .is_none_or(serde_json::Value::is_null)
        && *declared > have as u64
    {
        problems.push(format!(
            "/buffers/0 declares {declared} bytes, but the GLB binary chunk that holds it has \
             {have}; re-export the file"
        ));
    }
    let views: Vec<&serde_json::Value> = json["bufferViews"]
        .as_array()
        .into_iter()
        .flatten()
        .collect();
    for (i, view) in views.iter().enumerate() {
        let (Some(b), Some(length)) = (view["buffer"].as_u64(), view["byteLength"].as_u64()) else {
            continue;
        };
        let Some(Some(size)) = buffers.get(b as usize) else {
            continue;
        };
        let offset = view["byteOffset"].as_u64().unwrap_or(0);
        if offset.checked_add(length).is_none_or(|end| end > *size) {
            problems.push(format!(
                "/bufferViews/{i}: its {length} bytes from byteOffset {offset} run past the end \
                 of buffer {b} ({size} bytes)"
            ));
        }
    }
}

/// [`precheck`]: each accessor's and sparse accessor's bytes within their
/// buffer views.
fn check_accessors(json: &serde_json::Value, problems: &mut Vec<String>) {
    let views: Vec<&serde_json::Value> = json["bufferViews"]
        .as_array()
        .into_iter()
        .flatten()
        .collect();
    // Bytes `what` needs from `byteOffset` in buffer view `view`, checked
    // against the view's length.
    let mut fits =
        |at: String, view: &serde_json::Value, offset: &serde_json::Value, need: Option<u64>| {
            let Some(v) = view.as_u64() else { return };
            let Some(length) = views.get(v as usize).and_then(|x| x["byteLength"].as_u64()) else {
                return;
            };
            let offset = offset.as_u64().unwrap_or(0);
            let end = need.and_then(|n| n.checked_add(offset));
            if end.is_none_or(|end| end > length) {
                problems.push(format!(
                    "{at} need {} bytes from byteOffset {offset} of bufferView {v}, which holds \
                 {length}; fix its count or byteOffset",
                    need.map_or_else(|| "more".to_string(), |n| n.to_string())
                ));
            }
        };
    for (i, acc) in json["accessors"]
        .as_array()
        .into_iter()
        .flatten()
        .enumerate()
    {
        let Some(component) = component_bytes(&acc["componentType"]) else {
            continue;
        };
        let Some(element) = element_bytes(&acc["type"], component) else {
            continue;
        };
        let count = acc["count"].as_u64().unwrap_or(0);
        if count > 0 && !acc["bufferView"].is_null() {
            let stride = acc["bufferView"]
                .as_u64()
                .and_then(|v| views.get(v as usize))
                .and_then(|v| v["byteStride"].as_u64())
                .unwrap_or(element);
            let need = (count - 1)
                .checked_mul(stride)
                .and_then(|x| x.checked_add(element));
            fits(
                format!(
                    "/accessors/{i}: {count} {} elements",
                    acc["type"].as_str().unwrap_or("")
                ),
                &acc["bufferView"],
                &acc["byteOffset"],
                need,
            );
        }
        let sparse = &acc["sparse"];
        if let Some(n) = sparse["count"].as_u64() {
            let idx = &sparse["indices"];
            if let Some(c) = component_bytes(&idx["componentType"]) {
                fits(
                    format!("/accessors/{i}/sparse/indices: {n} indices"),
                    &idx["bufferView"],
                    &idx["byteOffset"],
                    n.checked_mul(c),
                );
            }
            let values = &sparse["values"];
            fits(
                format!("/accessors/{i}/sparse/values: {n} values"),
                &values["bufferView"],
                &values["byteOffset"],
                n.checked_mul(element),
            );
        }
    }
}

/// [`precheck`]: each image has exactly one source, and a MIME type with a
/// buffer view.
fn check_images(json: &serde_json::Value, problems: &mut Vec<String>) {
    for (i, image) in json["images"].as_array().into_iter().flatten().enumerate() {
        let has = |k: &str| image.get(k).is_some_and(|v| !v.is_null());
        let (uri, view, mime) = (has("uri"), has("bufferView"), has("mimeType"));
        let problem = match (uri, view) {
            (false, false) => Some(
                "has neither uri nor bufferView (a misspelt key?); give the image file's uri or \
                 its bufferView and mimeType"
                    .to_string(),
            ),
            (true, true) => Some("has both a uri and a bufferView; keep one".to_string()),
            (false, true) if !mime => Some(
                "has a bufferView but no mimeType; glTF requires it: add \"mimeType\": \
                 \"image/png\" (or image/jpeg)"
                    .to_string(),
            ),
            _ => None,
        };
        if let Some(what) = problem {
            problems.push(format!("/images/{i} {what}"));
        }
    }
}
