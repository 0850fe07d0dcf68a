//! The workspace's shape: no two files of a crate depend on each other, directly or through
//! others (issue 27: "no import circles between files").
//!
//! A file depends on another when it names an item of it: a `use` of a `crate::`, `super::` or
//! `self::` path, or such a path in its code (`crate::output::round(x, 1)`). Comments, strings
//! and `#[cfg(test)]` items are not read (tests may use anything); a module's own children and
//! ancestors do not count (a parent declares and re-exports its children, which use its
//! items: Rust's module tree, not a circle). Each crate's `src/` is read, without `src/bin/`
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
/// as its segments; `#[cfg(test)]` items skipped.
fn paths(tokens: TokenStream, out: &mut Vec<Vec<String>>) {
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

/// Reads the path starting at `tokens[i]` (after `prefix`), pushing each path it names (a
/// `{a, b::c}` group gives several); returns the index after it.
fn path_at(
    tokens: &[TokenTree],
    mut i: usize,
    mut prefix: Vec<String>,
    out: &mut Vec<Vec<String>>,
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
                for part in inner.split(|t| matches!(t, TokenTree::Punct(p) if p.as_char() == ','))
                {
                    if !part.is_empty() {
                        path_at(part, 0, prefix.clone(), out);
                    }
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
    out.push(prefix);
    i
}

/// The file-to-file dependencies of the crate at `src`: for each module, the modules it
/// names and, for each, the first path that names it.
fn dependencies(src: &Path) -> BTreeMap<Module, BTreeMap<Module, String>> {
    let files = modules(src);
    let mut deps: BTreeMap<Module, BTreeMap<Module, String>> = BTreeMap::new();
    for (module, path) in &files {
        let text = std::fs::read_to_string(path).unwrap();
        let tokens = TokenStream::from_str(&text)
            .unwrap_or_else(|e| panic!("{}: not Rust tokens: {e:?}", path.display()));
        let mut named = Vec::new();
        paths(tokens, &mut named);
        for segments in named {
            // Where the path starts: the crate root, this module, or its parents.
            let mut target: Module = match segments[0].as_str() {
                "crate" => Vec::new(),
                _ => module.clone(),
            };
            let mut rest = &segments[1..];
            if segments[0] == "super" {
                // `super` in `a/b.rs` (module a::b) is `a`; in `a/mod.rs` (module a), the root.
                target.pop();
                while rest.first().is_some_and(|s| s == "super") {
                    target.pop();
                    rest = &rest[1..];
                }
            }
            target.extend(rest.iter().cloned());
            // The file that holds it: the longest prefix that is a file.
            let Some(file) = (0..=target.len())
                .rev()
                .map(|k| target[..k].to_vec())
                .find(|m| files.contains_key(m))
            else {
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

/// The check finds a circle where there is one, through a `use` group, a `super::` path and a
/// path in code, and none in comments, strings or test modules.
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
}
