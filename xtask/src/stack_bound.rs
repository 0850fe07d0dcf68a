//! An upper bound of the firmware's stack, read off its disassembly (`llvm-objdump -d`): each
//! function's frame (its `push`, `vpush`, `stmdb sp!` and `sub sp, #n`), its calls (`bl`,
//! `blx` to a symbol) and tail calls (a branch to the start of another function); the deepest
//! call path from `Reset`, plus every exception handler of the vector table on top of it with
//! the hardware's exception frame (as if all of them nested at once). Stack painting measures
//! what a run used; this bounds what any run can use, so long as the code has no recursion, no
//! indirect calls and no frames sized at run time — which it checks, and refuses otherwise (a
//! cycle through the panic handler, a panic while logging a panic, is counted once: the run
//! ends there either way).

use anyhow::anyhow;
use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::process::Command;

use object::{Object, ObjectSection};

use crate::cargo::Step;

/// What the hardware pushes on exception entry with the FPU context (26 words), plus the
/// 4 bytes of alignment it may add.
const EXCEPTION_FRAME: u64 = 26 * 4 + 4;

/// The panic handler's symbol (cortex-m-rt / core: `rust_begin_unwind`).
const PANIC_HANDLER: &str = "rust_begin_unwind";

/// One function of the disassembly.
#[derive(Default)]
struct Function {
    frame: u64,
    calls: BTreeSet<String>,
    tail_calls: BTreeSet<String>,
    /// Why its stack use cannot be bounded (an indirect call, a frame sized at run time).
    unbounded: Option<String>,
}

/// A deepest path: its bytes and the (function, frame bytes) along it.
type Deepest = (u64, Vec<(String, u64)>);

/// The bound and how it is made up.
pub struct StackBound {
    /// Bytes: the deepest path from `Reset` plus every handler with its exception frame.
    pub bytes: u64,
    /// The deepest path from `Reset`, as (function, frame bytes).
    pub main_path: Vec<(String, u64)>,
    /// Each exception handler's own deepest path (bytes, without the exception frame).
    pub handlers: Vec<(String, u64)>,
}

/// The `llvm-objdump` to use: on `PATH` under its plain name or a versioned one.
pub fn objdump() -> Option<String> {
    let names = ["llvm-objdump".to_string()]
        .into_iter()
        .chain((14..=21).rev().map(|v| format!("llvm-objdump-{v}")));
    names.into_iter().find(|n| {
        Command::new(n)
            .arg("--version")
            .output()
            .is_ok_and(|o| o.status.success())
    })
}

/// The RAM target of issue 8: static RAM plus the stack bound within 8 KiB.
pub const RAM_LIMIT: u64 = 8 * 1024;

/// The flash target beside it: 32 KiB.
pub const FLASH_LIMIT: u64 = 32 * 1024;

/// The test step `name`: the release ELF at `elf` within the budget, its flash within
/// [`FLASH_LIMIT`] and its static RAM plus stack bound within [`RAM_LIMIT`].
pub fn budget_step(name: &str, elf: &Path) -> Step {
    let started = std::time::Instant::now();
    let measured = std::fs::read(elf)
        .map_err(|e| anyhow!("reading {}: {e}", elf.display()))
        .and_then(|bytes| crate::elf_size::footprint(&bytes))
        .and_then(|f| Ok((f, bound(elf)?)));
    let (ok, line) = match measured {
        Ok((f, b)) => {
            let ram = f.static_ram + b.bytes;
            (
                ram <= RAM_LIMIT && f.flash <= FLASH_LIMIT,
                format!(
                    "flash {} bytes of {FLASH_LIMIT}; RAM bound {ram} bytes (static {} + stack \
                     bound {}) of {RAM_LIMIT}",
                    f.flash, f.static_ram, b.bytes
                ),
            )
        }
        Err(e) => (false, format!("{e:#}")),
    };
    println!("\n==> {name}\n{line}");
    Step {
        name: name.to_string(),
        ok,
        summaries: vec![line],
        seconds: started.elapsed().as_secs_f64(),
    }
}

/// The bound for the ELF at `elf`.
pub fn bound(elf: &Path) -> anyhow::Result<StackBound> {
    let tool = objdump()
        .ok_or_else(|| anyhow!("llvm-objdump not found (Debian: apt-get install llvm)"))?;
    let out = Command::new(&tool)
        .args(["-d", "--no-show-raw-insn", "--demangle"])
        .arg(elf)
        .output()
        .map_err(|e| anyhow!("running {tool}: {e}"))?;
    if !out.status.success() {
        return Err(anyhow!(
            "{tool} failed: {}",
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    let (functions, by_address) = parse(&String::from_utf8_lossy(&out.stdout))?;
    let bytes = std::fs::read(elf).map_err(|e| anyhow!("reading {}: {e}", elf.display()))?;
    let vectors = vector_table(&bytes)?;
    let name_at = |address: u64| {
        by_address
            .get(&(address & !1))
            .cloned()
            .ok_or_else(|| anyhow!("no function at vector address {address:#x}"))
    };
    let reset = name_at(
        *vectors
            .first()
            .ok_or_else(|| anyhow!("empty vector table"))?,
    )?;
    let mut memo = BTreeMap::new();
    let (main_bytes, main_path) = deepest(&functions, &reset, &mut Vec::new(), &mut memo)?;
    let mut handlers = BTreeSet::new();
    for &address in &vectors[1..] {
        handlers.insert(name_at(address)?);
    }
    let mut total = main_bytes;
    let mut handler_depths = Vec::new();
    for h in handlers {
        let (d, _) = deepest(&functions, &h, &mut Vec::new(), &mut memo)?;
        total += d + EXCEPTION_FRAME;
        handler_depths.push((h, d));
    }
    Ok(StackBound {
        bytes: total,
        main_path,
        handlers: handler_depths,
    })
}

/// The exception vectors after the initial stack pointer: `Reset` first, then every handler
/// (addresses with the Thumb bit).
fn vector_table(elf: &[u8]) -> anyhow::Result<Vec<u64>> {
    let file = object::File::parse(elf).map_err(|e| anyhow!("parsing the ELF: {e}"))?;
    let section = file
        .section_by_name(".vector_table")
        .ok_or_else(|| anyhow!("no .vector_table section"))?;
    let data = section.data().map_err(|e| anyhow!("{e}"))?;
    let words: Vec<u64> = data
        .chunks_exact(4)
        .map(|w| u64::from(u32::from_le_bytes([w[0], w[1], w[2], w[3]])))
        .collect();
    // Word 0 is the initial stack pointer; unused vectors are 0.
    Ok(words.into_iter().skip(1).filter(|&w| w != 0).collect())
}

/// The deepest path from `f`: bytes and the frames along it.
fn deepest(
    functions: &BTreeMap<String, Function>,
    f: &str,
    stack: &mut Vec<String>,
    memo: &mut BTreeMap<String, Deepest>,
) -> anyhow::Result<Deepest> {
    if let Some(known) = memo.get(f) {
        return Ok(known.clone());
    }
    if let Some(start) = stack.iter().position(|s| s == f) {
        // The one cycle accepted goes through the panic handler (a panic while logging a
        // panic): it ends the run either way, so each function is counted once along it.
        let cycle = format!("{} -> {f}", stack[start..].join(" -> "));
        if stack[start..].iter().any(|s| s.contains(PANIC_HANDLER)) {
            return Ok((0, Vec::new()));
        }
        return Err(anyhow!("recursion, no bound: {cycle}"));
    }
    let function = functions
        .get(f)
        .ok_or_else(|| anyhow!("call to {f}, which the disassembly does not have"))?;
    if let Some(why) = &function.unbounded {
        return Err(anyhow!("{f}: {why}"));
    }
    stack.push(f.to_string());
    let mut best = (function.frame, vec![(f.to_string(), function.frame)]);
    for callee in &function.calls {
        let (d, path) = deepest(functions, callee, stack, memo)?;
        if function.frame + d > best.0 {
            best = (
                function.frame + d,
                std::iter::once((f.to_string(), function.frame))
                    .chain(path)
                    .collect(),
            );
        }
    }
    // A tail call leaves after the caller's frame is popped.
    for callee in &function.tail_calls {
        let (d, path) = deepest(functions, callee, stack, memo)?;
        if d > best.0 {
            best = (
                d,
                std::iter::once((format!("{f} (tail call)"), 0))
                    .chain(path)
                    .collect(),
            );
        }
    }
    stack.pop();
    memo.insert(f.to_string(), best.clone());
    Ok(best)
}

/// Functions by name, and names by start address.
#[allow(clippy::type_complexity)]
fn parse(listing: &str) -> anyhow::Result<(BTreeMap<String, Function>, BTreeMap<u64, String>)> {
    let mut functions: BTreeMap<String, Function> = BTreeMap::new();
    let mut by_address: BTreeMap<u64, String> = BTreeMap::new();
    // Other names of a function (symbols at the same address, e.g. `Reset` and `__stext`).
    let mut aliases: BTreeMap<String, String> = BTreeMap::new();
    let mut current: Option<String> = None;
    for line in listing.lines() {
        // A symbol: `00000476 <name>:`. Mapping symbols (`$t`, `$d`) only mark code and data.
        if let Some((address, rest)) = line.split_once(" <") {
            if let (Ok(address), Some(name)) = (
                u64::from_str_radix(address.trim(), 16),
                rest.strip_suffix(">:"),
            ) {
                if !name.starts_with('$') {
                    match by_address.get(&address) {
                        Some(first) => {
                            aliases.insert(name.to_string(), first.clone());
                            current = Some(first.clone());
                        }
                        None => {
                            by_address.insert(address, name.to_string());
                            functions.entry(name.to_string()).or_default();
                            current = Some(name.to_string());
                        }
                    }
                }
                continue;
            }
        }
        // An instruction: `     400:      \tbl\t0x3702 <name> @ imm = #13054`.
        let (Some(name), Some((_, instruction))) = (&current, line.split_once(':')) else {
            continue;
        };
        let instruction = instruction.split(" @ ").next().unwrap_or("").trim();
        let (mnemonic, operands) = instruction.split_once('\t').unwrap_or((instruction, ""));
        let f = functions.entry(name.clone()).or_default();
        read_instruction(f, name, mnemonic, operands.trim());
    }
    // Calls name whichever symbol the disassembler chose: resolve them to the function.
    let resolve = |set: &BTreeSet<String>| {
        set.iter()
            .map(|n| aliases.get(n).unwrap_or(n).clone())
            .collect()
    };
    for f in functions.values_mut() {
        f.calls = resolve(&f.calls);
        f.tail_calls = resolve(&f.tail_calls);
    }
    Ok((functions, by_address))
}

/// Adds what one instruction does to the stack or the call graph to `f`.
fn read_instruction(f: &mut Function, name: &str, mnemonic: &str, operands: &str) {
    let registers = |list: &str| -> u64 {
        let inner = list
            .split_once('{')
            .and_then(|(_, r)| r.split_once('}'))
            .map_or("", |(r, _)| r);
        inner
            .split(',')
            .map(str::trim)
            .filter(|r| !r.is_empty())
            .map(|r| match r.split_once('-') {
                // A range of VFP registers: d8-d15 or s16-s31.
                Some((a, b)) => {
                    let n = |s: &str| s[1..].parse::<u64>().unwrap_or(0);
                    let size = if a.starts_with('d') { 8 } else { 4 };
                    (n(b) + 1).saturating_sub(n(a)) * size
                }
                None => {
                    if r.starts_with('d') {
                        8
                    } else {
                        4
                    }
                }
            })
            .sum()
    };
    let base = mnemonic.trim_end_matches(".w");
    match base {
        "push" | "vpush" => f.frame += registers(operands),
        "stmdb" if operands.starts_with("sp!") => f.frame += registers(operands),
        "vstmdb" if operands.starts_with("sp!") => f.frame += registers(operands),
        "sub" | "subw" | "subs" if operands.starts_with("sp,") => {
            match operands
                .rsplit_once('#')
                .and_then(|(_, n)| parse_immediate(n))
            {
                Some(n) => f.frame += n,
                None => {
                    f.unbounded = Some(format!(
                        "stack frame sized at run time ({mnemonic} {operands})"
                    ))
                }
            }
        }
        "bl" | "blx" => match target(operands) {
            Some(t) if is_mapping_symbol(&t) => {}
            Some(t) => {
                f.calls.insert(t);
            }
            None => f.unbounded = Some(format!("indirect call ({mnemonic} {operands})")),
        },
        _ => {
            // A branch to the start of another function is a tail call.
            let is_branch = mnemonic.starts_with('b')
                && !mnemonic.starts_with("bic")
                && !mnemonic.starts_with("bfi")
                && !mnemonic.starts_with("bkpt");
            if is_branch {
                if let Some(t) = target(operands) {
                    if t != name && !operands.contains('+') && !is_mapping_symbol(&t) {
                        f.tail_calls.insert(t);
                    }
                }
            }
        }
    }
}

/// The symbol of a direct branch's operands, `0x1234 <name>` (without an offset into it).
fn target(operands: &str) -> Option<String> {
    let (_, rest) = operands.split_once('<')?;
    let name = rest.strip_suffix('>')?;
    Some(name.split("+0x").next().unwrap_or(name).to_string())
}

/// Whether a branch target is a mapping symbol (`$t`, `$d`): a place inside the function the
/// disassembler is in, not another function.
fn is_mapping_symbol(name: &str) -> bool {
    name.starts_with('$')
}

fn parse_immediate(s: &str) -> Option<u64> {
    let s = s.trim();
    match s.strip_prefix("0x") {
        Some(hex) => u64::from_str_radix(hex, 16).ok(),
        None => s.parse().ok(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn function(lines: &[(&str, &str)]) -> Function {
        let mut f = Function::default();
        for (m, o) in lines {
            read_instruction(&mut f, "me", m, o);
        }
        f
    }

    #[test]
    fn frames_count_pushes_vpushes_and_sp_subtractions() {
        let f = function(&[
            ("push", "{r4, r5, r6, r7, lr}"),
            ("push.w", "{r8, r9, r10, r11}"),
            ("vpush", "{d8, d9}"),
            ("vpush", "{s16-s19}"),
            ("sub", "sp, #204"),
            ("subw", "sp, sp, #2456"),
            ("sub.w", "sp, sp, #0x100"),
            ("sub", "r0, r1, #8"),
        ]);
        assert_eq!(f.frame, 20 + 16 + 16 + 16 + 204 + 2456 + 256);
        assert!(f.unbounded.is_none());
    }

    #[test]
    fn calls_tail_calls_and_what_cannot_be_bounded() {
        let f = function(&[
            ("bl", "0x23d4 <a::b>"),
            ("b.w", "0x2d22 <c>"),
            ("bne", "0x2402 <me+0x2e>"),
            ("beq.w", "0x2500 <d>"),
        ]);
        assert_eq!(f.calls.iter().collect::<Vec<_>>(), ["a::b"]);
        assert_eq!(f.tail_calls.iter().collect::<Vec<_>>(), ["c", "d"]);
        assert!(function(&[("blx", "r3")]).unbounded.is_some());
        assert!(function(&[("sub.w", "sp, sp, r0")]).unbounded.is_some());
    }

    #[test]
    fn the_deepest_path_adds_frames_and_tail_calls_reuse_the_callers_space() {
        let mut functions = BTreeMap::new();
        functions.insert(
            "a".to_string(),
            Function {
                frame: 100,
                calls: ["b", "c"].map(String::from).into(),
                ..Function::default()
            },
        );
        functions.insert(
            "b".to_string(),
            Function {
                frame: 50,
                ..Function::default()
            },
        );
        functions.insert(
            "c".to_string(),
            Function {
                frame: 10,
                tail_calls: ["d".to_string()].into(),
                ..Function::default()
            },
        );
        functions.insert(
            "d".to_string(),
            Function {
                frame: 70,
                ..Function::default()
            },
        );
        let (bytes, path) =
            deepest(&functions, "a", &mut Vec::new(), &mut BTreeMap::new()).unwrap();
        assert_eq!(bytes, 170);
        assert_eq!(path.last().unwrap().0, "d");
        functions.insert(
            "d".to_string(),
            Function {
                frame: 1,
                calls: ["a".to_string()].into(),
                ..Function::default()
            },
        );
        assert!(deepest(&functions, "a", &mut Vec::new(), &mut BTreeMap::new()).is_err());
    }
}
