//! The workspace's shape: no two files of a crate depend on each other, directly or through
//! others (issue 27: "no import circles between files").
//!
//! A file depends on another when it names an item of it: a `use` of a `crate::`, `super::` or
//! `self::` path, or such a path in its code (`crate::number::round(x, 1)`), followed through
//! re-exports (`crate::Polynomial`, which `lib.rs` re-exports, is `polynomial.rs`'s; globs are
//! not followed). Comments, strings and `#[cfg(test)]` items are not read (tests may use
//! anything); a module's own children and ancestors do not count (a parent declares and
//! re-exports its children, which use its items: Rust's module tree, not a circle). Each crate's `src/` is read, without `src/bin/`
//! (separate crates). The files are lexed with `proc-macro2`, Rust's own token rules, so a path
//! in a comment or a string is never taken for a dependency.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::str::FromStr;

use proc_macro2::{Delimiter, Spacing, TokenStream, TokenTree};

/// A module's path in its crate (`["cli", "gait"]`); the crate root is empty.
type Module = Vec<String>;

/// Every `.rs` file below `src` (without `src/bin`), by module path.
fn modules(src: &Path) -> BTreeMap<Module, PathBuf> {
    fn walk(dir: &Path, src: &Path, out: &mut BTreeMap<Module, PathBuf>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() {
                if path != src.join("bin") {
                    walk(&path, src, out);
                }
            } else if path.extension().is_some_and(|e| e == "rs") {
                let rel = path.strip_prefix(src).unwrap().with_extension("");
                let mut module: Module = rel
                    .components()
                    .map(|c| c.as_os_str().to_string_lossy().into_owned())
                    .collect();
                if matches!(
                    module.last().map(String::as_str),
                    Some("mod" | "lib" | "main")
                ) {
                    module.pop();
                }
                // A test module in a file of its own (`#[cfg(test)] mod tests;`).
                if module.last().is_some_and(|m| m == "tests") {
                    continue;
                }
                out.insert(module, path);
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(src, src, &mut out);
    out
}

/// The `crate::`, `super::` and `self::` paths named in `tokens` (use trees expanded), each
/// with the name it goes by; `#[cfg(test)]` items skipped.
fn paths(tokens: TokenStream, out: &mut Vec<Leaf>) {
    let tokens: Vec<TokenTree> = tokens.into_iter().collect();
    let mut i = 0;
    while i < tokens.len() {
        if is_cfg_test(&tokens, i) {
            i = item_end(&tokens, i + 2);
            continue;
        }
        match &tokens[i] {
            TokenTree::Ident(id)
                if matches!(id.to_string().as_str(), "crate" | "super" | "self")
                    && is_path_sep(&tokens, i + 1) =>
            {
                i = path_at(&tokens, i, Vec::new(), out);
            }
            TokenTree::Group(g) => {
                paths(g.stream(), out);
                i += 1;
            }
            _ => i += 1,
        }
    }
}

/// Whether `tokens[i..]` starts with `::`.
fn is_path_sep(tokens: &[TokenTree], i: usize) -> bool {
    matches!(
        (tokens.get(i), tokens.get(i.wrapping_add(1))),
        (Some(TokenTree::Punct(a)), Some(TokenTree::Punct(b)))
            if a.as_char() == ':' && a.spacing() == Spacing::Joint && b.as_char() == ':'
    )
}

/// Whether `tokens[i..]` is the attribute `#[cfg(test)]`.
fn is_cfg_test(tokens: &[TokenTree], i: usize) -> bool {
    match (tokens.get(i), tokens.get(i + 1)) {
        (Some(TokenTree::Punct(p)), Some(TokenTree::Group(g)))
            if p.as_char() == '#' && g.delimiter() == Delimiter::Bracket =>
        {
            let inner: String = g.stream().to_string().split_whitespace().collect();
            inner == "cfg(test)"
        }
        _ => false,
    }
}

/// The index after the item starting at `i`: through its first `{ ... }` or `;` at this level.
fn item_end(tokens: &[TokenTree], mut i: usize) -> usize {
    while let Some(t) = tokens.get(i) {
        i += 1;
        match t {
            TokenTree::Group(g) if g.delimiter() == Delimiter::Brace => break,
            TokenTree::Punct(p) if p.as_char() == ';' => break,
            _ => {}
        }
    }
    i
}

/// A path's segments and the name it goes by (its last segment, or its `as` alias).
type Leaf = (Vec<String>, String);

/// Reads the path starting at `tokens[i]` (after `prefix`), pushing each path it names (a
/// `{a, b::c}` group gives several; `a::{self}` is `a`); returns the index after it.
fn path_at(
    tokens: &[TokenTree],
    mut i: usize,
    mut prefix: Vec<String>,
    out: &mut Vec<Leaf>,
) -> usize {
    loop {
        match tokens.get(i) {
            Some(TokenTree::Ident(id)) => {
                prefix.push(id.to_string());
                i += 1;
            }
            Some(TokenTree::Group(g)) if g.delimiter() == Delimiter::Brace => {
                // A use tree's group: each comma-separated part continues the prefix.
                let inner: Vec<TokenTree> = g.stream().into_iter().collect();
                let comma = |t: &TokenTree| matches!(t, TokenTree::Punct(p) if p.as_char() == ',');
                for part in inner.split(comma).filter(|p| !p.is_empty()) {
                    path_at(part, 0, prefix.clone(), out);
                }
                return i + 1;
            }
            _ => break,
        }
        if is_path_sep(tokens, i) {
            i += 2;
        } else {
            break;
        }
    }
    let alias = match (tokens.get(i), tokens.get(i + 1)) {
        (Some(TokenTree::Ident(a)), Some(TokenTree::Ident(b))) if a == "as" => Some(b.to_string()),
        _ => None,
    };
    if prefix.last().is_some_and(|s| s == "self") {
        prefix.pop();
    }
    if let Some(name) = alias.or_else(|| prefix.last().cloned()) {
        out.push((prefix, name));
    }
    i
}

/// The `pub use` (and `pub(crate) use`) trees at the top of a file's `tokens`.
fn pub_uses(tokens: &[TokenTree]) -> Vec<Vec<TokenTree>> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < tokens.len() {
        if is_cfg_test(tokens, i) {
            i = item_end(tokens, i + 2);
            continue;
        }
        let is = |k: usize, word: &str| matches!(tokens.get(k), Some(TokenTree::Ident(id)) if id == word);
        if is(i, "pub") {
            let after = match tokens.get(i + 1) {
                Some(TokenTree::Group(g)) if g.delimiter() == Delimiter::Parenthesis => i + 2,
                _ => i + 1,
            };
            if is(after, "use") {
                let end = item_end(tokens, after + 1);
                let tree: Vec<TokenTree> = tokens[after + 1..end]
                    .iter()
                    .filter(|t| !matches!(t, TokenTree::Punct(p) if p.as_char() == ';'))
                    .cloned()
                    .collect();
                out.push(tree);
                i = end;
                continue;
            }
        }
        i += 1;
    }
    out
}

/// `segments` (a path as written in `module`) from the crate root, if it is this crate's.
fn absolute(
    segments: &[String],
    module: &Module,
    files: &BTreeMap<Module, PathBuf>,
) -> Option<Module> {
    let first = segments.first()?;
    let (mut target, mut rest): (Module, &[String]) = match first.as_str() {
        "crate" => (Vec::new(), &segments[1..]),
        "self" => (module.clone(), &segments[1..]),
        "super" => (module.clone(), segments),
        // A child module of this one (a `pub use child::Item` in a `mod.rs` or `lib.rs`).
        child if files.contains_key(&[module.as_slice(), &[child.to_string()]].concat()) => {
            (module.clone(), segments)
        }
        _ => return None,
    };
    // `super` in `a/b.rs` (module a::b) is `a`; in `a/mod.rs` (module a), the root.
    while rest.first().is_some_and(|s| s == "super") {
        target.pop();
        rest = &rest[1..];
    }
    target.extend(rest.iter().cloned());
    Some(target)
}

/// The file-to-file dependencies of the crate at `src`: for each module, the modules it
/// names and, for each, the first path that names it. A path to an item a module re-exports
/// (`crate::Polynomial`, re-exported by `lib.rs`) is followed to the file that holds it.
fn dependencies(src: &Path) -> BTreeMap<Module, BTreeMap<Module, String>> {
    let files = modules(src);
    let mut named: BTreeMap<Module, Vec<Leaf>> = BTreeMap::new();
    // For each file, what it re-exports: a name and the path it stands for.
    let mut reexports: BTreeMap<Module, BTreeMap<String, Module>> = BTreeMap::new();
    for (module, path) in &files {
        let text = std::fs::read_to_string(path).unwrap();
        let tokens = TokenStream::from_str(&text)
            .unwrap_or_else(|e| panic!("{}: not Rust tokens: {e:?}", path.display()));
        let top: Vec<TokenTree> = tokens.clone().into_iter().collect();
        for tree in pub_uses(&top) {
            let mut leaves = Vec::new();
            path_at(&tree, 0, Vec::new(), &mut leaves);
            for (segments, name) in leaves {
                if let Some(target) = absolute(&segments, module, &files) {
                    reexports
                        .entry(module.clone())
                        .or_default()
                        .insert(name, target);
                }
            }
        }
        paths(tokens, named.entry(module.clone()).or_default());
    }
    // The file that holds what `target` names: the longest prefix that is a file, through
    // the re-exports on the way.
    let holder = |mut target: Module| -> Option<Module> {
        for _ in 0..16 {
            let file = (0..=target.len())
                .rev()
                .map(|k| target[..k].to_vec())
                .find(|m| files.contains_key(m))?;
            let through = target[file.len()..]
                .first()
                .and_then(|name| reexports.get(&file)?.get(name));
            match through {
                Some(path) => {
                    let next: Module = path
                        .iter()
                        .chain(&target[file.len() + 1..])
                        .cloned()
                        .collect();
                    if next == target {
                        return Some(file);
                    }
                    target = next;
                }
                None => return Some(file),
            }
        }
        None
    };
    let mut deps: BTreeMap<Module, BTreeMap<Module, String>> = BTreeMap::new();
    for (module, paths) in &named {
        for (segments, _) in paths {
            let Some(file) = absolute(segments, module, &files).and_then(&holder) else {
                continue;
            };
            let related = file.starts_with(module) || module.starts_with(&file);
            if !related {
                deps.entry(module.clone())
                    .or_default()
                    .entry(file)
                    .or_insert_with(|| segments.join("::"));
            }
        }
    }
    deps
}

/// The circles among `deps`: groups of two or more modules that each reach the others.
fn circles(deps: &BTreeMap<Module, BTreeMap<Module, String>>) -> Vec<BTreeSet<Module>> {
    let nodes: BTreeSet<&Module> = deps
        .keys()
        .chain(deps.values().flat_map(|d| d.keys()))
        .collect();
    let reach = |from: &Module| -> BTreeSet<Module> {
        let mut seen = BTreeSet::new();
        let mut stack = vec![from.clone()];
        while let Some(m) = stack.pop() {
            for next in deps.get(&m).into_iter().flat_map(|d| d.keys()) {
                if seen.insert(next.clone()) {
                    stack.push(next.clone());
                }
            }
        }
        seen
    };
    let reached: BTreeMap<&Module, BTreeSet<Module>> =
        nodes.iter().map(|m| (*m, reach(m))).collect();
    let mut out: Vec<BTreeSet<Module>> = Vec::new();
    for m in &nodes {
        if !reached[m].contains(*m) || out.iter().any(|c| c.contains(*m)) {
            continue;
        }
        let circle: BTreeSet<Module> = nodes
            .iter()
            .filter(|n| reached[m].contains(**n) && reached[**n].contains(*m))
            .map(|n| (*n).clone())
            .collect();
        out.push(circle);
    }
    out
}

/// Every crate's `src/` in the workspace and the firmware.
fn crate_sources() -> Vec<PathBuf> {
    let root = qgait_system_tests::root();
    let mut out: Vec<PathBuf> = ["host", "tests", "xtask", "firmware"]
        .iter()
        .map(|c| root.join(c).join("src"))
        .collect();
    for entry in std::fs::read_dir(root.join("crates")).unwrap().flatten() {
        out.push(entry.path().join("src"));
    }
    out.retain(|p| p.is_dir());
    out.sort();
    out
}

#[test]
fn no_file_depends_on_itself_through_others() {
    let sources = crate_sources();
    assert!(sources.len() >= 15, "crates found: {sources:?}");
    let mut report = Vec::new();
    for src in &sources {
        let deps = dependencies(src);
        for circle in circles(&deps) {
            let name = |m: &Module| {
                if m.is_empty() {
                    "(root)".to_string()
                } else {
                    m.join("/")
                }
            };
            let mut lines = vec![format!(
                "{}: {}",
                src.display(),
                circle.iter().map(name).collect::<Vec<_>>().join(", ")
            )];
            for from in &circle {
                for (to, why) in &deps[from] {
                    if circle.contains(to) {
                        lines.push(format!("  {} -> {} ({why})", name(from), name(to)));
                    }
                }
            }
            report.push(lines.join("\n"));
        }
    }
    assert!(
        report.is_empty(),
        "files that depend on themselves:\n{}",
        report.join("\n")
    );
}

/// The check finds a circle where there is one, through a `use` group, a `super::` path, a
/// path in code and re-exports, and none in comments, strings or test modules.
#[test]
fn the_check_sees_circles_and_only_circles() {
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path().join("src");
    std::fs::create_dir_all(src.join("a")).unwrap();
    let write = |file: &str, text: &str| std::fs::write(src.join(file), text).unwrap();
    write("lib.rs", "pub mod a;\npub mod b;\npub mod c;\npub mod d;\n");
    write("a/mod.rs", "pub mod inner;\nuse self::inner::X;\n");
    write("a/inner.rs", "pub struct X;\nuse super::super::b::Y;\n");
    write("b.rs", "pub struct Y;\nfn f() { crate::c::g(); }\n");
    write("c.rs", "use crate::{d::Z, a::inner::X};\npub fn g() {}\n");
    write(
        "d.rs",
        "pub struct Z;\n// crate::b::Y\nconst S: &str = \"crate::c::g\";\n\
         #[cfg(test)]\nmod tests { use crate::b::Y; }\n",
    );
    let deps = dependencies(&src);
    let found = circles(&deps);
    let m = |s: &str| s.split('/').map(String::from).collect::<Module>();
    assert_eq!(
        found,
        vec![[m("a/inner"), m("b"), m("c")].into_iter().collect()],
        "{deps:?}"
    );
    assert!(!deps.contains_key(&m("d")), "{deps:?}");
    // Without the path in code, no circle.
    write("b.rs", "pub struct Y;\n");
    assert!(circles(&dependencies(&src)).is_empty());
    // A circle through re-exports: `d` names `Y` at the root, which re-exports `b`'s, and
    // `b` names `Z` through `c`'s re-export of `d`'s.
    write(
        "lib.rs",
        "pub mod a;\npub mod b;\npub mod c;\npub mod d;\npub use b::{Y as Why};\n",
    );
    write("c.rs", "pub use crate::d::Z;\npub fn g() {}\n");
    write("d.rs", "pub struct Z;\nfn f(_: crate::Why) {}\n");
    write("b.rs", "pub struct Y;\nuse super::c::Z;\n");
    assert_eq!(
        circles(&dependencies(&src)),
        vec![[m("b"), m("d")].into_iter().collect()]
    );
}
