//! The dependency direction of ARCHITECTURE.md, enforced: each room of `src/`
//! may name only the rooms listed for it, each sub-room of `src/rig/` only the
//! sub-rooms below it, no files of `src/` import each other in a cycle (one
//! graph of the whole crate, every file its own node), no command of
//! `src/cmd/` names another (only the shared `mod.rs`, `args.rs`, `out.rs`),
//! and the rooms that must not know about files, plots or templates use none
//! of those crates.
//!
//! Paths are read with `syn` from the code outside tests (`#[cfg(test)]` items
//! and `tests.rs` / `*_tests.rs` files are left out): `use` trees, every path
//! in code and types, and `a::b` paths inside macro calls. A path is resolved
//! the way the compiler resolves it: `crate::`, `self::` and `super::` (also
//! inside inline modules), a name a `use` brought in, or a child module; then
//! through re-exports (`pub use`) to the file that defines the item, so
//! `crate::rig::AuditedRig` counts as a use of `rig/judge/audited.rs`. A
//! re-export is not itself a use: a facade such as `rig/mod.rs` depends on
//! nothing.

use rayon::prelude::*;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use syn::visit::{self, Visit};

/// Each room and the rooms it may depend on (ARCHITECTURE.md, "The rooms", its last column).
const ALLOWED: &[(&str, &[&str])] = &[
    ("stats", &[]),
    ("atomic", &[]),
    ("format", &["stats"]),
    ("dataset", &["stats", "format", "atomic"]),
    ("error", &["dataset"]),
    ("analysis", &["dataset", "stats", "format"]),
    (
        "synth",
        &["analysis", "dataset", "stats", "format", "atomic"],
    ),
    (
        "rig",
        &["analysis", "dataset", "stats", "format", "atomic", "error"],
    ),
    (
        "track",
        &["analysis", "dataset", "stats", "format", "atomic", "error"],
    ),
    (
        "report",
        &[
            "rig", "analysis", "dataset", "stats", "format", "atomic", "error",
        ],
    ),
    (
        "cmd",
        &[
            "report", "track", "rig", "analysis", "dataset", "stats", "format", "atomic", "error",
            "synth",
        ],
    ),
    ("cli", &["cmd", "error"]),
];

/// Each sub-room of `src/rig/` and the sub-rooms it may depend on
/// (ARCHITECTURE.md, the rig row): read <- find (the fingers found on a
/// hand's skin) <- judge <- fix <- make (a hand's fingers placed and
/// weighted, written by fix's one writer); deform on read and judge; session
/// on top. `rig/mod.rs` itself only declares and re-exports.
const RIG_ALLOWED: &[(&str, &[&str])] = &[
    ("read", &[]),
    ("find", &["read"]),
    ("judge", &["read", "find"]),
    ("fix", &["read", "judge"]),
    ("make", &["read", "find", "judge", "fix"]),
    ("deform", &["read", "judge"]),
    (
        "session",
        &["read", "find", "judge", "fix", "make", "deform"],
    ),
];

/// Crates a room must not use: the statistics know nothing of files, plots,
/// templates or glTF; the rig knows nothing of plots or templates, and its
/// judgement nothing of files or glTF.
const FORBIDDEN: &[(&str, &[&str])] = &[
    (
        "stats",
        &["std::fs", "plotters", "tera", "gltf", "serde_json"],
    ),
    ("analysis", &["std::fs", "plotters", "tera", "gltf"]),
    ("dataset", &["plotters", "tera", "gltf"]),
    ("rig", &["plotters", "tera"]),
    ("rig/judge", &["std::fs", "gltf"]),
];

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

/// The `.rs` files of a room (a directory or a single file under src/). The
/// statistics core is its own crate, `crates/stats` (re-exported as `stats`), so
/// the compiler keeps it from naming any other room; its files are read here
/// for the crates it must not use.
fn files(room: &str) -> Vec<PathBuf> {
    let dir = if room == "stats" {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("crates/stats/src")
    } else {
        src().join(room)
    };
    if dir.is_dir() {
        let mut out = Vec::new();
        let mut stack = vec![dir];
        while let Some(d) = stack.pop() {
            for e in std::fs::read_dir(&d).expect("read src dir") {
                let p = e.expect("dir entry").path();
                if p.is_dir() {
                    stack.push(p);
                } else if p.extension().is_some_and(|x| x == "rs") {
                    out.push(p);
                }
            }
        }
        out.sort();
        out
    } else {
        vec![src().join(format!("{room}.rs"))]
    }
}

/// True for files that are test modules themselves (`tests.rs`, `*_tests.rs`).
fn is_test_file(path: &Path) -> bool {
    path.file_name()
        .and_then(|n| n.to_str())
        .is_some_and(|n| n.ends_with("tests.rs"))
}

/// The code of a file without comments and without its test modules (everything
/// from the first `#[cfg(test)]` on, which by convention ends each file), and
/// without files that are test modules themselves. For the crate checks.
fn code(path: &Path) -> String {
    if is_test_file(path) {
        return String::new();
    }
    let text = std::fs::read_to_string(path).expect("read source");
    let body = text.split("#[cfg(test)]").next().unwrap_or_default();
    body.lines()
        .map(|l| l.split("//").next().unwrap_or_default())
        .collect::<Vec<_>>()
        .join("\n")
}

/// A module path from the crate root, e.g. `["rig", "read", "skin"]`.
type ModPath = Vec<String>;

fn mod_path(parts: &[&str]) -> ModPath {
    parts.iter().map(|s| s.to_string()).collect()
}

/// One leaf of a `use` tree: where it stands, what it names, the name it
/// brings in (`*` for a glob), and whether it is a re-export (`pub use`).
#[derive(Debug, Clone)]
struct Use {
    scope: ModPath,
    path: Vec<String>,
    name: String,
    reexport: bool,
}

/// What one file names, outside its tests.
#[derive(Debug, Default, Clone)]
struct Scanned {
    uses: Vec<Use>,
    /// (scope, path) of every path in code, types and macro calls.
    paths: Vec<(ModPath, Vec<String>)>,
    /// Inline modules (`mod x { ... }`) by their full path.
    inline: BTreeSet<ModPath>,
}

fn is_cfg_test(attrs: &[syn::Attribute]) -> bool {
    attrs.iter().any(|a| match &a.meta {
        syn::Meta::List(l) => l.path.is_ident("cfg") && l.tokens.to_string() == "test",
        _ => false,
    })
}

fn item_attrs(item: &syn::Item) -> &[syn::Attribute] {
    use syn::Item::*;
    match item {
        Const(i) => &i.attrs,
        Enum(i) => &i.attrs,
        ExternCrate(i) => &i.attrs,
        Fn(i) => &i.attrs,
        ForeignMod(i) => &i.attrs,
        Impl(i) => &i.attrs,
        Macro(i) => &i.attrs,
        Mod(i) => &i.attrs,
        Static(i) => &i.attrs,
        Struct(i) => &i.attrs,
        Trait(i) => &i.attrs,
        TraitAlias(i) => &i.attrs,
        Type(i) => &i.attrs,
        Union(i) => &i.attrs,
        Use(i) => &i.attrs,
        _ => &[],
    }
}

/// The leaves of a `use` tree under `prefix`: (path, name brought in).
fn use_leaves(tree: &syn::UseTree, prefix: &mut Vec<String>, out: &mut Vec<(Vec<String>, String)>) {
    let leaf = |prefix: &[String], ident: &syn::Ident| -> Vec<String> {
        let mut p = prefix.to_vec();
        if ident != "self" {
            p.push(ident.to_string());
        }
        p
    };
    match tree {
        syn::UseTree::Path(p) => {
            prefix.push(p.ident.to_string());
            use_leaves(&p.tree, prefix, out);
            prefix.pop();
        }
        syn::UseTree::Name(n) => {
            let path = leaf(prefix, &n.ident);
            let name = path.last().cloned().unwrap_or_default();
            out.push((path, name));
        }
        syn::UseTree::Rename(r) => out.push((leaf(prefix, &r.ident), r.rename.to_string())),
        syn::UseTree::Glob(_) => out.push((prefix.clone(), "*".to_string())),
        syn::UseTree::Group(g) => {
            for t in &g.items {
                use_leaves(t, prefix, out);
            }
        }
    }
}

/// `a::b::c` paths inside a macro call's tokens (format!, matches!, ...).
fn token_paths(tokens: proc_macro2::TokenStream, out: &mut Vec<Vec<String>>) {
    use proc_macro2::TokenTree;
    let mut current: Vec<String> = Vec::new();
    let mut colons = 0;
    let flush = |current: &mut Vec<String>, out: &mut Vec<Vec<String>>| {
        if current.len() > 1 {
            out.push(std::mem::take(current));
        }
        current.clear();
    };
    for t in tokens {
        match t {
            TokenTree::Ident(i) => {
                if colons == 2 && !current.is_empty() {
                    current.push(i.to_string());
                } else {
                    flush(&mut current, out);
                    current.push(i.to_string());
                }
                colons = 0;
            }
            TokenTree::Punct(p) if p.as_char() == ':' => colons += 1,
            TokenTree::Group(g) => {
                flush(&mut current, out);
                colons = 0;
                token_paths(g.stream(), out);
            }
            _ => {
                flush(&mut current, out);
                colons = 0;
            }
        }
    }
    flush(&mut current, out);
}

/// Walks a file's items, keeping the module it is in (inline modules too).
struct Scan<'s> {
    here: ModPath,
    out: &'s mut Scanned,
}

impl<'ast> Visit<'ast> for Scan<'_> {
    fn visit_item(&mut self, i: &'ast syn::Item) {
        if !is_cfg_test(item_attrs(i)) {
            visit::visit_item(self, i);
        }
    }

    fn visit_impl_item_fn(&mut self, f: &'ast syn::ImplItemFn) {
        if !is_cfg_test(&f.attrs) {
            visit::visit_impl_item_fn(self, f);
        }
    }

    fn visit_item_mod(&mut self, m: &'ast syn::ItemMod) {
        // `mod x;` declares a file: not a use of it.
        if let Some((_, items)) = &m.content {
            self.here.push(m.ident.to_string());
            self.out.inline.insert(self.here.clone());
            for i in items {
                self.visit_item(i);
            }
            self.here.pop();
        }
    }

    fn visit_visibility(&mut self, _: &'ast syn::Visibility) {
        // `pub(crate)`, `pub(super)`: who may see an item, not a use.
    }

    fn visit_item_use(&mut self, u: &'ast syn::ItemUse) {
        if u.leading_colon.is_some() {
            return; // `use ::name`: another crate
        }
        let mut leaves = Vec::new();
        use_leaves(&u.tree, &mut Vec::new(), &mut leaves);
        let reexport = !matches!(u.vis, syn::Visibility::Inherited);
        for (path, name) in leaves {
            self.out.uses.push(Use {
                scope: self.here.clone(),
                path,
                name,
                reexport,
            });
        }
    }

    fn visit_path(&mut self, p: &'ast syn::Path) {
        if p.leading_colon.is_none() {
            let segs = p.segments.iter().map(|s| s.ident.to_string()).collect();
            self.out.paths.push((self.here.clone(), segs));
        }
        visit::visit_path(self, p);
    }

    fn visit_macro(&mut self, m: &'ast syn::Macro) {
        let mut found = Vec::new();
        token_paths(m.tokens.clone(), &mut found);
        for segs in found {
            self.out.paths.push((self.here.clone(), segs));
        }
        visit::visit_macro(self, m);
    }
}

/// Scans the source of the file of module `module`; a file that does not parse fails the test.
fn scan(module: &ModPath, source: &str, label: &str) -> Scanned {
    let file = syn::parse_file(source).unwrap_or_else(|e| panic!("{label} does not parse: {e}"));
    let mut out = Scanned::default();
    let mut s = Scan {
        here: module.clone(),
        out: &mut out,
    };
    for i in &file.items {
        s.visit_item(i);
    }
    out
}

/// The module of a file under src/: `rig/read/mod.rs` is `rig::read`,
/// `rig/read/skin.rs` is `rig::read::skin`, `lib.rs` the crate root.
fn module_of(file: &Path) -> ModPath {
    let rel = file.strip_prefix(src()).expect("a file under src/");
    let mut parts: Vec<String> = rel
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    let last = parts.pop().unwrap_or_default();
    let stem = last.trim_end_matches(".rs");
    if !(stem == "mod" || (stem == "lib" && parts.is_empty())) {
        parts.push(stem.to_string());
    }
    parts
}

/// The library crate: every file's module and what it names.
#[derive(Clone)]
struct Crate {
    /// File modules: module path -> file.
    modules: BTreeMap<ModPath, PathBuf>,
    /// Inline modules of every file.
    inline: BTreeSet<ModPath>,
    scanned: BTreeMap<PathBuf, Scanned>,
}

impl Crate {
    /// Every file of src/ (not main.rs, the binary), read and scanned once per
    /// test process: parsing the 1.4 MB of src/ takes seconds in a debug build.
    fn real() -> &'static Crate {
        static REAL: OnceLock<Crate> = OnceLock::new();
        REAL.get_or_init(|| {
            let all: Vec<(ModPath, PathBuf)> = files("")
                .into_iter()
                .filter(|f| *f != src().join("main.rs"))
                .map(|f| (module_of(&f), f))
                .collect();
            let scanned = all
                .par_iter()
                .map(|(module, file)| {
                    let source = if is_test_file(file) {
                        String::new()
                    } else {
                        std::fs::read_to_string(file).expect("read source")
                    };
                    (
                        file.clone(),
                        scan(module, &source, &file.display().to_string()),
                    )
                })
                .collect();
            Crate::of(all.into_iter().collect(), scanned)
        })
    }

    /// The crate with `overrides` (module, source) in place of the files of those modules.
    fn with(overrides: &[(ModPath, &str)]) -> Crate {
        let real = Crate::real();
        let mut scanned = real.scanned.clone();
        for (module, source) in overrides {
            let file = real.modules[module].clone();
            let label = format!("the snippet for {}", file.display());
            scanned.insert(file, scan(module, source, &label));
        }
        Crate::of(real.modules.clone(), scanned)
    }

    fn of(modules: BTreeMap<ModPath, PathBuf>, scanned: BTreeMap<PathBuf, Scanned>) -> Crate {
        let inline = scanned.values().flat_map(|s| s.inline.clone()).collect();
        Crate {
            modules,
            inline,
            scanned,
        }
    }

    /// True when `m` is a module: a file's or an inline one.
    fn is_module(&self, m: &ModPath) -> bool {
        self.modules.contains_key(m) || self.inline.contains(m)
    }

    /// The absolute path of `segs` as written in `scope` of `file`: through
    /// `crate`, `self`, `super`, a name a `use` of that scope brought in, or a
    /// child module; `None` for another crate's path or a local name.
    fn absolute(
        &self,
        file: &Path,
        scope: &ModPath,
        segs: &[String],
        depth: usize,
    ) -> Option<ModPath> {
        let first = segs.first()?;
        if depth > 16 {
            return None;
        }
        if first == "crate" {
            return Some(segs[1..].to_vec());
        }
        if first == "self" || first == "super" {
            let mut cur = scope.clone();
            let mut i = 0;
            while let Some(s) = segs.get(i) {
                match s.as_str() {
                    "self" => {}
                    "super" => {
                        cur.pop()?;
                    }
                    _ => break,
                }
                i += 1;
            }
            cur.extend_from_slice(&segs[i..]);
            return Some(cur);
        }
        let s = &self.scanned[file];
        if let Some(u) = s
            .uses
            .iter()
            .find(|u| u.scope == *scope && u.name == *first && u.path != segs)
        {
            let mut abs = self.absolute(file, &u.scope, &u.path, depth + 1)?;
            abs.extend_from_slice(&segs[1..]);
            return Some(abs);
        }
        let mut child = scope.clone();
        child.push(first.clone());
        self.is_module(&child).then(|| {
            let mut abs = scope.clone();
            abs.extend_from_slice(segs);
            abs
        })
    }

    /// The absolute path of a path in `file`'s code, as [`Crate::absolute`],
    /// but `None` for a lone name that resolves to a module: in code a single
    /// name is a value or a type (a local `groups` beside `mod groups`), never
    /// a module.
    fn code_absolute(&self, file: &Path, scope: &ModPath, segs: &[String]) -> Option<ModPath> {
        let abs = self.absolute(file, scope, segs, 0)?;
        (segs.len() > 1 || !self.is_module(&abs)).then_some(abs)
    }

    /// The files an absolute path passes through: the file of its longest
    /// module prefix, then, while the next name is one that file brings in by
    /// a `use`, the file that name comes from. The last is where it is defined.
    fn files_of(&self, abs: &ModPath) -> Vec<PathBuf> {
        let mut out = Vec::new();
        let mut abs = abs.clone();
        for _ in 0..16 {
            let Some(k) = (0..=abs.len())
                .rev()
                .find(|&k| self.modules.contains_key(&abs[..k]))
            else {
                break;
            };
            let file = self.modules[&abs[..k]].clone();
            out.push(file.clone());
            let Some(name) = abs.get(k) else { break };
            let module = abs[..k].to_vec();
            let s = &self.scanned[&file];
            let Some(u) = s.uses.iter().find(|u| u.scope == module && u.name == *name) else {
                break;
            };
            let Some(mut next) = self.absolute(&file, &u.scope, &u.path, 0) else {
                break;
            };
            next.extend_from_slice(&abs[k + 1..]);
            abs = next;
        }
        out
    }

    /// Per file, the files each of its names passes through (see
    /// [`Crate::files_of`]): its private `use`s and every path of its code.
    /// A `pub use` is not a use of its own.
    fn named(&self, file: &Path) -> Vec<Vec<PathBuf>> {
        let s = &self.scanned[file];
        let uses = s
            .uses
            .iter()
            .filter(|u| !u.reexport)
            .map(|u| (u.scope.clone(), u.path.clone()));
        let uses = uses.filter_map(|(scope, segs)| self.absolute(file, &scope, &segs, 0));
        let code = s
            .paths
            .iter()
            .filter_map(|(scope, segs)| self.code_absolute(file, scope, segs));
        uses.chain(code)
            .map(|abs| self.files_of(&abs))
            .filter(|chain| !chain.is_empty())
            .collect()
    }

    /// The file graph: each file to the files that define what it names.
    fn graph(&self, under: &str) -> BTreeMap<PathBuf, BTreeSet<PathBuf>> {
        let root = src().join(under);
        let mut g = BTreeMap::new();
        for file in self.scanned.keys().filter(|f| f.starts_with(&root)) {
            let to: BTreeSet<PathBuf> = self
                .named(file)
                .into_iter()
                .filter_map(|chain| chain.last().cloned())
                .filter(|t| t != file && t.starts_with(&root))
                .collect();
            g.insert(file.clone(), to);
        }
        g
    }

    /// The file graph of room `under` one level deep: a file directly in it is
    /// its own node; a sub-folder and its files are one node, named by the
    /// sub-folder's module file (`report/plots/*.rs` are `report/plots.rs`).
    fn flat_graph(&self, under: &str) -> BTreeMap<PathBuf, BTreeSet<PathBuf>> {
        let root = src().join(under);
        let node = |f: &Path| -> PathBuf {
            let rel = f.strip_prefix(&root).expect("a file of the room");
            let mut parts = rel.components();
            let first = parts.next().expect("a name").as_os_str().to_owned();
            if parts.next().is_none() {
                return f.to_path_buf();
            }
            let file = root.join(&first).with_extension("rs");
            if file.is_file() {
                file
            } else {
                root.join(&first).join("mod.rs")
            }
        };
        let mut g: BTreeMap<PathBuf, BTreeSet<PathBuf>> = BTreeMap::new();
        for (from, to) in self.graph(under) {
            let from = node(&from);
            let to: Vec<PathBuf> = to.iter().map(|t| node(t)).filter(|t| *t != from).collect();
            g.entry(from).or_default().extend(to);
        }
        g
    }
}

/// The room of a file (the first name of its module) and, for a file of
/// `rig`, its sub-room (`None` for `rig/mod.rs`).
fn room_of(file: &Path) -> (Option<String>, Option<String>) {
    let m = module_of(file);
    let room = m.first().cloned();
    let sub = (room.as_deref() == Some("rig"))
        .then(|| m.get(1).cloned())
        .flatten();
    (room, sub)
}

/// The names of `files` against a table: "file uses room" for each room (or,
/// with `rig`, each sub-room of `rig`) a file names and may not use.
fn against(
    krate: &Crate,
    files: &[PathBuf],
    table: &[(&str, &[&str])],
    rig: bool,
) -> BTreeMap<String, BTreeSet<String>> {
    // A file's room, or with `rig` its sub-room (`None` outside rig/ and for rig/mod.rs).
    let level = |f: &Path| -> Option<String> {
        let (room, sub) = room_of(f);
        if rig {
            (room.as_deref() == Some("rig")).then_some(sub).flatten()
        } else {
            room
        }
    };
    let mut wrong: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for file in files {
        let Some(mine) = level(file) else { continue };
        let Some((_, allowed)) = table.iter().find(|(r, _)| *r == mine) else {
            continue;
        };
        for chain in krate.named(file) {
            for target in chain {
                let Some(used) = level(&target) else { continue };
                let known = table.iter().any(|(r, _)| *r == used);
                if known && used != mine && !allowed.contains(&used.as_str()) {
                    wrong
                        .entry(file.display().to_string())
                        .or_default()
                        .insert(format!("uses {used}"));
                }
            }
        }
    }
    wrong
}

/// The files of `src/cmd/` every command may use: the option groups, standard
/// output and the module's shared helpers. Every other file there is a command.
const CMD_SHARED: &[&str] = &["mod", "args", "out"];

/// The command a file of `src/cmd/` belongs to (`cmd/deform.rs` -> `deform`);
/// `None` for a shared file ([`CMD_SHARED`]) and for files outside `cmd/`.
fn command_of(file: &Path) -> Option<String> {
    let m = module_of(file);
    match m.as_slice() {
        [room, name, ..] if room == "cmd" && !CMD_SHARED.contains(&name.as_str()) => {
            Some(name.clone())
        }
        _ => None,
    }
}

/// Per command file, the other commands it names: through `super::x`,
/// `crate::cmd::x`, `self::super::x` or a `use` of one, in a `use` (a `pub
/// use` too) or in a path of its code, outside its tests.
fn commands_named(krate: &Crate) -> BTreeMap<String, BTreeSet<String>> {
    let mut wrong: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (file, s) in &krate.scanned {
        let Some(mine) = command_of(file) else {
            continue;
        };
        let uses = s
            .uses
            .iter()
            .filter_map(|u| krate.absolute(file, &u.scope, &u.path, 0));
        let code = s
            .paths
            .iter()
            .filter_map(|(scope, segs)| krate.code_absolute(file, scope, segs));
        for abs in uses.chain(code) {
            for target in krate.files_of(&abs) {
                if let Some(used) = command_of(&target)
                    && used != mine
                {
                    wrong
                        .entry(file.display().to_string())
                        .or_default()
                        .insert(format!("uses cmd/{used}"));
                }
            }
        }
    }
    wrong
}

/// The cycles of a graph: its strongly connected components of more than one
/// node (Tarjan's algorithm, O(nodes + edges)), each sorted.
fn cycles<N: Ord + Clone>(g: &BTreeMap<N, BTreeSet<N>>) -> Vec<Vec<N>> {
    struct Tarjan<'g, N: Ord> {
        g: &'g BTreeMap<N, BTreeSet<N>>,
        index: BTreeMap<&'g N, usize>,
        low: BTreeMap<&'g N, usize>,
        stack: Vec<&'g N>,
        on: BTreeSet<&'g N>,
        out: Vec<Vec<N>>,
    }
    impl<'g, N: Ord + Clone> Tarjan<'g, N> {
        fn visit(&mut self, v: &'g N) {
            let i = self.index.len();
            self.index.insert(v, i);
            self.low.insert(v, i);
            self.stack.push(v);
            self.on.insert(v);
            let g = self.g;
            for w in g.get(v).into_iter().flatten() {
                if !self.index.contains_key(w) {
                    self.visit(w);
                    let lw = self.low[w];
                    let lv = self.low.get_mut(v).expect("visited");
                    *lv = (*lv).min(lw);
                } else if self.on.contains(w) {
                    let iw = self.index[w];
                    let lv = self.low.get_mut(v).expect("visited");
                    *lv = (*lv).min(iw);
                }
            }
            if self.low[v] == self.index[v] {
                let mut scc = Vec::new();
                while let Some(w) = self.stack.pop() {
                    self.on.remove(w);
                    scc.push(w.clone());
                    if w == v {
                        break;
                    }
                }
                if scc.len() > 1 {
                    scc.sort();
                    self.out.push(scc);
                }
            }
        }
    }
    let mut t = Tarjan {
        g,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on: BTreeSet::new(),
        out: Vec::new(),
    };
    for v in g.keys() {
        if !t.index.contains_key(v) {
            t.visit(v);
        }
    }
    t.out
}

/// The rooms a snippet names, as the file of module `at`.
fn rooms_named(at: &[&str], snippet: &str) -> BTreeSet<String> {
    let krate = Crate::with(&[(mod_path(at), snippet)]);
    let file = krate.modules[&mod_path(at)].clone();
    krate
        .named(&file)
        .into_iter()
        .flatten()
        .filter_map(|f| room_of(&f).0)
        .collect()
}

#[test]
fn every_room_depends_only_on_the_rooms_below_it() {
    let krate = Crate::real();
    let all: Vec<PathBuf> = krate.scanned.keys().cloned().collect();
    let wrong = against(krate, &all, ALLOWED, false);
    assert!(
        wrong.is_empty(),
        "dependencies against ARCHITECTURE.md: {wrong:#?}"
    );
}

#[test]
fn every_sub_room_of_rig_depends_only_on_the_sub_rooms_below_it() {
    let krate = Crate::real();
    let all: Vec<PathBuf> = krate.scanned.keys().cloned().collect();
    let wrong = against(krate, &all, RIG_ALLOWED, true);
    assert!(
        wrong.is_empty(),
        "dependencies inside rig/ against ARCHITECTURE.md (read <- find <- judge <- fix <- \
         make; deform on read and judge; session on top): {wrong:#?}"
    );
}

#[test]
fn no_command_uses_another_command() {
    // What two commands share lives in the library (or in cmd/args.rs,
    // cmd/out.rs, cmd/mod.rs): a command calls the library, never another command.
    let krate = Crate::real();
    let commands: BTreeSet<String> = krate.scanned.keys().filter_map(|f| command_of(f)).collect();
    assert!(
        commands.len() > 15 && commands.contains("report") && commands.contains("deform"),
        "the commands of src/cmd/: {commands:?}"
    );
    let wrong = commands_named(krate);
    assert!(
        wrong.is_empty(),
        "commands using other commands (move what they share into the library): {wrong:#?}"
    );
}

#[test]
fn the_scanner_sees_a_command_use_another() {
    // The uses the commands had: a `super::` path, a `crate::cmd::` path, a
    // `use` of a sibling command, and a name brought in from one.
    let krate = Crate::with(&[
        (
            mod_path(&["cmd", "report"]),
            "fn f() { let r = super::deform::request(); super::groups_of(); \
             super::args::parse_sims(\"1\"); }",
        ),
        (
            mod_path(&["cmd", "coverage"]),
            "fn g() { crate::cmd::report::check_coverage_budget(); crate::cmd::out::print(); }",
        ),
        (
            mod_path(&["cmd", "import"]),
            "use super::add;\nfn h() { add::print_outcome(); }",
        ),
        (
            mod_path(&["cmd", "remove"]),
            "use crate::cmd::add::rows_text;\nuse super::out;\nfn k() { rows_text(1); }\n\
             #[cfg(test)]\nmod tests { use crate::cmd::deform::Args; }",
        ),
        // The shared files may name the commands (cmd/mod.rs dispatches to them).
        (mod_path(&["cmd"]), "fn d() { self::deform::run(); }"),
    ]);
    let wrong = commands_named(&krate);
    let at = |f: &str| {
        wrong
            .get(&src().join(f).display().to_string())
            .cloned()
            .unwrap_or_default()
            .into_iter()
            .collect::<Vec<_>>()
    };
    assert_eq!(at("cmd/report.rs"), ["uses cmd/deform"]);
    assert_eq!(at("cmd/coverage.rs"), ["uses cmd/report"]);
    assert_eq!(at("cmd/import.rs"), ["uses cmd/add"]);
    assert_eq!(at("cmd/remove.rs"), ["uses cmd/add"]);
    assert_eq!(wrong.len(), 4, "{wrong:#?}");
}

#[test]
fn rig_mod_rs_only_declares_and_re_exports() {
    // The facade names nothing itself, so no sub-room can reach another through it.
    let named = Crate::real().named(&src().join("rig/mod.rs"));
    assert!(named.is_empty(), "rig/mod.rs names {named:?}");
}

/// The files and folders of `dir` (by stem, but `skip`) missing from `table`.
fn missing_from(dir: &Path, table: &[(&str, &[&str])], skip: &[&str]) -> Vec<String> {
    let mut missing = Vec::new();
    for e in std::fs::read_dir(dir).expect("read a src dir") {
        let p = e.expect("dir entry").path();
        let name = p
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or_default()
            .to_string();
        if !skip.contains(&name.as_str()) && !table.iter().any(|(r, _)| *r == name) {
            missing.push(name);
        }
    }
    missing
}

#[test]
fn every_room_of_src_is_in_the_map() {
    let missing = missing_from(&src(), ALLOWED, &["lib", "main"]);
    assert!(
        missing.is_empty(),
        "rooms of src/ missing from ARCHITECTURE.md and tests/architecture.rs: {missing:?}"
    );
}

#[test]
fn every_sub_room_of_rig_is_in_the_map() {
    let missing = missing_from(&src().join("rig"), RIG_ALLOWED, &["mod"]);
    assert!(
        missing.is_empty(),
        "sub-rooms of src/rig/ missing from ARCHITECTURE.md and tests/architecture.rs: {missing:?}"
    );
}

#[test]
fn no_import_cycle_among_the_files_of_rig() {
    let g = Crate::real().graph("rig");
    assert!(g.len() > 20, "the rig graph has only {} files", g.len());
    let edges: usize = g.values().map(BTreeSet::len).sum();
    assert!(edges > 40, "the rig graph has only {edges} edges");
    // Edges the code is known to have (the old cycle's, now one way).
    for (from, to) in [
        ("rig/read/skin.rs", "rig/read/gltf.rs"),
        ("rig/read/weights.rs", "rig/read/skin.rs"),
        ("rig/judge/bend.rs", "rig/read/weights.rs"),
        ("rig/fix/remap.rs", "rig/judge/bend.rs"),
        ("rig/fix/mod.rs", "rig/fix/remap.rs"),
        ("rig/session.rs", "rig/fix/mod.rs"),
        ("rig/deform/hand.rs", "rig/read/recognise.rs"),
    ] {
        let (from, to) = (src().join(from), src().join(to));
        assert!(
            g[&from].contains(&to),
            "{} -> {}: {:?}",
            from.display(),
            to.display(),
            g[&from]
        );
    }
    let found = cycles(&g);
    assert!(
        found.is_empty(),
        "import cycles among the files of rig/: {found:#?}"
    );
}

/// A file's path relative to src/, for messages.
fn rel(f: &Path) -> String {
    f.strip_prefix(src()).unwrap_or(f).display().to_string()
}

/// Each cycle of `g` with the edges among its files, relative to src/, for messages.
fn cycles_told(g: &BTreeMap<PathBuf, BTreeSet<PathBuf>>) -> Vec<Vec<String>> {
    cycles(g)
        .iter()
        .map(|c| {
            c.iter()
                .flat_map(|a| {
                    g[a].iter()
                        .filter(|b| c.contains(b))
                        .map(move |b| format!("{} -> {}", rel(a), rel(b)))
                })
                .collect()
        })
        .collect()
}

#[test]
fn no_import_cycle_anywhere_in_src() {
    // One graph of every file of src/ (a `mod.rs` is a file like any other):
    // `crate::`, `self::` and `super::` paths, across rooms and inside them.
    let g = Crate::real().graph("");
    assert!(g.len() > 150, "the crate graph has only {} files", g.len());
    let edges: usize = g.values().map(BTreeSet::len).sum();
    assert!(edges > 500, "the crate graph has only {edges} edges");
    // Edges the code is known to have: across rooms, and the old cycles' (a
    // mod.rs and its children), now one way.
    for (from, to) in [
        ("analysis/mod.rs", "dataset/mod.rs"),
        ("analysis/groups.rs", "analysis/compare.rs"),
        ("analysis/compare.rs", "analysis/mod.rs"),
        ("dataset/mod.rs", "dataset/tip.rs"),
        ("dataset/tip_rows.rs", "dataset/mod.rs"),
        ("dataset/tip_rows.rs", "dataset/tip.rs"),
        ("dataset/landmarks/mod.rs", "dataset/landmarks/atlas37.rs"),
        ("dataset/landmarks/atlas37.rs", "dataset/landmarks/hand.rs"),
        ("dataset/landmarks/checks.rs", "dataset/landmarks/hand.rs"),
        ("rig/fix/remap.rs", "rig/judge/bend.rs"),
    ] {
        let (from, to) = (src().join(from), src().join(to));
        assert!(
            g[&from].contains(&to),
            "{} -> {}: {:?}",
            rel(&from),
            rel(&to),
            g[&from]
        );
    }
    let found = cycles_told(&g);
    assert!(
        found.is_empty(),
        "import cycles among the files of src/ (each with its edges; move what a \
         mod.rs and its children share into a leaf file and re-export it): {found:#?}"
    );
}

#[test]
fn the_cycle_finder_sees_a_cycle_across_rooms() {
    // The dataset naming the analysis (a `super::super::` path in code) while
    // the analysis names the dataset (a `use`): one cycle of two rooms' files.
    let krate = Crate::with(&[
        (
            mod_path(&["dataset", "quantity"]),
            "fn f() { let _ = super::super::analysis::compare::welch; }",
        ),
        (
            mod_path(&["analysis", "compare"]),
            "use crate::dataset::Quantity;\nfn g(q: Quantity) {}",
        ),
    ]);
    let (quantity, compare) = (
        src().join("dataset/quantity.rs"),
        src().join("analysis/compare.rs"),
    );
    let g = krate.graph("");
    assert!(g[&quantity].contains(&compare), "{:?}", g[&quantity]);
    assert!(g[&compare].contains(&quantity), "{:?}", g[&compare]);
    let found = cycles(&g);
    assert!(found.contains(&vec![compare, quantity]), "{found:#?}");
    // A lone name that is also a child module's (a local `groups` in
    // analysis/mod.rs) names no module.
    let krate = Crate::with(&[(
        mod_path(&["analysis"]),
        "pub mod groups;\nfn f(groups: Vec<u8>) -> usize { groups.len() }",
    )]);
    let mod_rs = src().join("analysis/mod.rs");
    assert!(krate.graph("analysis")[&mod_rs].is_empty());
}

#[test]
fn no_import_cycle_among_the_files_of_report() {
    // `plots/` and `plots.rs` count as one file.
    let g = Crate::real().flat_graph("report");
    assert!(g.len() > 15, "the report graph has only {} files", g.len());
    let edges: usize = g.values().map(BTreeSet::len).sum();
    assert!(edges > 20, "the report graph has only {edges} edges");
    // Edges the code is known to have (the old cycles', now one way): the words
    // both comparisons share below them, the sentences terminal and report share
    // below both, the sections below the report's view.
    for (from, to) in [
        ("report/compare.rs", "report/compare_table.rs"),
        ("report/compare.rs", "report/compare_words.rs"),
        ("report/compare_table.rs", "report/compare_words.rs"),
        ("report/text.rs", "report/phrases.rs"),
        ("report/view.rs", "report/sections/mod.rs"),
        ("report/sections/mod.rs", "report/phrases.rs"),
    ] {
        let (from, to) = (src().join(from), src().join(to));
        assert!(
            g[&from].contains(&to),
            "{} -> {}: {:?}",
            from.display(),
            to.display(),
            g[&from]
        );
    }
    for (from, to) in [
        ("report/compare_table.rs", "report/compare.rs"),
        ("report/view.rs", "report/text.rs"),
    ] {
        let (from, to) = (src().join(from), src().join(to));
        assert!(
            !g[&from].contains(&to),
            "{} -> {}",
            from.display(),
            to.display()
        );
    }
    let found = cycles(&g);
    assert!(
        found.is_empty(),
        "import cycles among the files of report/: {found:#?}"
    );
}

#[test]
fn the_cycle_finder_sees_the_old_cycles_of_report() {
    // compare_table naming compare again (`use super::x`), and view naming text
    // (a `super::x::` path in code and a `crate::report::x` path in a macro
    // call) while text names view, each naming items the other file defines.
    let krate = Crate::with(&[
        (
            mod_path(&["report", "compare_table"]),
            "use super::compare::{cohort_line, mean_sd};\nfn f(c: &C) -> String { cohort_line(c) }",
        ),
        (
            mod_path(&["report", "view"]),
            "fn g(a: &A) -> String { super::text::check(a, 80) }\n\
             fn h() -> String { format!(\"{}\", crate::report::text::RECORDS_SHOWN) }\n\
             pub struct ReportView;",
        ),
        (
            mod_path(&["report", "text"]),
            "use super::view::ReportView;\nfn k(v: &ReportView) {}\npub fn check() {}\npub const RECORDS_SHOWN: usize = 3;",
        ),
    ]);
    let g = krate.flat_graph("report");
    let (compare, table, text, view) = (
        src().join("report/compare.rs"),
        src().join("report/compare_table.rs"),
        src().join("report/text.rs"),
        src().join("report/view.rs"),
    );
    assert!(g[&table].contains(&compare), "{:?}", g[&table]);
    assert!(g[&view].contains(&text), "{:?}", g[&view]);
    let found = cycles(&g);
    assert!(found.contains(&vec![compare, table]), "{found:#?}");
    assert!(found.contains(&vec![text, view]), "{found:#?}");
}

#[test]
fn the_statistics_crate_depends_on_none_of_the_file_plot_or_template_crates() {
    let manifest = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("crates/stats/Cargo.toml"),
    )
    .expect("crates/stats/Cargo.toml");
    let deps = manifest
        .split("[dependencies]")
        .nth(1)
        .and_then(|rest| rest.split("\n[").next())
        .expect("a [dependencies] table");
    let names: Vec<&str> = deps
        .lines()
        .filter_map(|l| l.split('=').next())
        .map(str::trim)
        .filter(|n| !n.is_empty() && !n.starts_with('#'))
        .collect();
    assert!(names.contains(&"rayon"), "{names:?}");
    for c in ["csv", "plotters", "tera", "gltf", "serde_json", "phalanx"] {
        assert!(
            !names.contains(&c),
            "crates/stats depends on {c}: {names:?}"
        );
    }
}

#[test]
fn the_statistics_know_nothing_of_files_plots_or_templates() {
    let mut wrong = Vec::new();
    for (room, crates) in FORBIDDEN {
        for file in files(room) {
            let code = code(&file);
            for c in *crates {
                if code.contains(&format!("{c}::")) || code.contains(&format!("use {c}")) {
                    wrong.push(format!("{} uses {c}", file.display()));
                }
            }
        }
    }
    assert!(wrong.is_empty(), "{wrong:#?}");
}

#[test]
fn the_scanner_sees_a_forbidden_edge() {
    // The tests above would pass vacuously if the scanner found nothing.
    let used = rooms_named(
        &["analysis"],
        "use crate::{report, dataset::Row};\nfn f(p: &Path) { let x = crate::rig::Rig::load(p); }",
    );
    assert_eq!(
        used.into_iter().collect::<Vec<_>>(),
        vec!["dataset", "report", "rig"]
    );
    assert!(code(&src().join("analysis/mod.rs")).contains("crate::dataset"));
    // Through a re-export: rig::naming::Side is the dataset's Side.
    let used = rooms_named(&["report", "view"], "fn f(s: crate::rig::naming::Side) {}");
    assert!(used.contains("rig") && used.contains("dataset"), "{used:?}");
}

#[test]
fn the_scanner_sees_back_edges_inside_rig() {
    // A `super::fix` use from read and a `crate::rig::fix` path from judge.
    let overrides = [
        (
            mod_path(&["rig", "read"]),
            "use super::fix::Fixed;\npub use gltf::GltfFile;",
        ),
        (
            mod_path(&["rig", "judge", "finger"]),
            "pub fn f() { let _ = crate::rig::fix::fix; }",
        ),
        // `self::super::`, inside an inline module, and a path in a macro call.
        (
            mod_path(&["rig", "read", "gltf"]),
            "mod inner { fn g() { self::super::super::super::session::audit(); } }\n\
             fn h() { println!(\"{}\", crate::rig::judge::TIP_INSIDE); }\n\
             #[cfg(test)]\nmod tests { use crate::rig::fix::Fixed; }",
        ),
        // A module brought in by `use`, then named relatively.
        (
            mod_path(&["rig", "read", "skin"]),
            "use crate::rig::deform as d;\nfn k() { d::deform(); }",
        ),
    ];
    let krate = Crate::with(&overrides);
    let changed: Vec<PathBuf> = overrides
        .iter()
        .map(|(m, _)| krate.modules[m].clone())
        .collect();
    let wrong = against(&krate, &changed, RIG_ALLOWED, true);
    let at = |f: &str| {
        wrong
            .get(&src().join(f).display().to_string())
            .cloned()
            .unwrap_or_default()
            .into_iter()
            .collect::<Vec<_>>()
    };
    assert_eq!(at("rig/read/mod.rs"), ["uses fix"]);
    assert_eq!(at("rig/judge/finger.rs"), ["uses fix"]);
    // The test module's `fix` is not counted; the session and judge paths are.
    assert_eq!(at("rig/read/gltf.rs"), ["uses judge", "uses session"]);
    assert_eq!(at("rig/read/skin.rs"), ["uses deform"]);
    // A relative `use` of a sibling sub-room from the facade.
    let krate = Crate::with(&[(mod_path(&["rig"]), "pub mod read;\nuse judge::AuditedRig;")]);
    assert_eq!(
        krate.named(&src().join("rig/mod.rs")),
        [vec![
            src().join("rig/judge/mod.rs"),
            src().join("rig/judge/audited.rs")
        ]]
    );
}

#[test]
fn the_cycle_finder_sees_a_cycle() {
    let g: BTreeMap<u8, BTreeSet<u8>> = [
        (1, BTreeSet::from([2])),
        (2, BTreeSet::from([3])),
        (3, BTreeSet::from([1, 4])),
        (4, BTreeSet::from([5])),
        (5, BTreeSet::new()),
    ]
    .into_iter()
    .collect();
    assert_eq!(cycles(&g), vec![vec![1, 2, 3]]);
    // A cycle like the one of old: the reader naming the writer, and the
    // writer the reader.
    let krate = Crate::with(&[
        (
            mod_path(&["rig", "read", "skin"]),
            "use crate::rig::fix::remap::Remapped;",
        ),
        (
            mod_path(&["rig", "fix", "remap"]),
            "use crate::rig::read::skin::SkinnedMesh;",
        ),
    ]);
    let found = cycles(&krate.graph("rig"));
    assert_eq!(
        found,
        vec![vec![
            src().join("rig/fix/remap.rs"),
            src().join("rig/read/skin.rs")
        ]]
    );
}

/// Every `.rs` file of the two crates as ARCHITECTURE.md names it: a file of
/// `src/` by its path under `src/` (`report/plots/draw.rs`, `lib.rs`), a file
/// of the statistics crate by its path in the repository
/// (`crates/stats/src/bootstrap.rs`); test files too.
fn source_files() -> Vec<String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut out: Vec<String> = files("")
        .iter()
        .map(|f| rel(f))
        .chain(
            files("stats")
                .iter()
                .map(|f| f.strip_prefix(root).unwrap_or(f).display().to_string()),
        )
        .map(|p| p.replace('\\', "/"))
        .collect();
    out.sort();
    out
}

fn architecture_md() -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("ARCHITECTURE.md"))
        .expect("ARCHITECTURE.md")
}

#[test]
fn every_source_file_is_named_in_architecture_md() {
    // A file is named by a line of its own, "- `report/plots/draw.rs` — its role":
    // one line per file, as the map promises.
    let map = architecture_md();
    let all = source_files();
    assert!(
        all.len() > 150 && all.contains(&"crates/stats/src/lib.rs".to_string()),
        "{all:?}"
    );
    let missing: Vec<&String> = all
        .iter()
        .filter(|f| !map.contains(&format!("\n- `{f}` — ")))
        .collect();
    assert!(
        missing.is_empty(),
        "files ARCHITECTURE.md does not name (give each a line such as \
         \"- `dataset/tip.rs` — its role\", its path under src/, or under the \
         repository for crates/stats): {missing:#?}"
    );
}

#[test]
fn every_file_the_list_of_architecture_md_names_exists() {
    // The lines "- `path.rs` — role", anywhere on the page: a moved or removed
    // file leaves the map with it.
    let map = architecture_md();
    let all = source_files();
    let listed: Vec<&str> = map
        .lines()
        .filter_map(|l| l.strip_prefix("- `"))
        .filter_map(|l| l.split('`').next())
        .filter(|f| f.ends_with(".rs"))
        .collect();
    assert!(
        listed.len() > 150,
        "the map lists only {} files",
        listed.len()
    );
    let gone: Vec<&str> = listed
        .into_iter()
        .filter(|f| !all.iter().any(|a| a == f))
        .collect();
    assert!(
        gone.is_empty(),
        "files the list of ARCHITECTURE.md names that are not there: {gone:#?}"
    );
}
