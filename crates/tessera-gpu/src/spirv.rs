//! The little SPIR-V reflection Tessera needs: workgroup sizes (so dispatch helpers can turn
//! thread counts into group counts), struct member offsets (so a test can hold host structs
//! to the shader's layout) and how often a function is inlined (drivers inline every call, so
//! a shader's compile time grows with that count).

const OP_NAME: u32 = 5;
const OP_MEMBER_NAME: u32 = 6;
const OP_EXECUTION_MODE: u32 = 16;
const OP_MEMBER_DECORATE: u32 = 72;
const OP_ENTRY_POINT: u32 = 15;
const OP_FUNCTION: u32 = 54;
const OP_FUNCTION_END: u32 = 56;
const OP_FUNCTION_CALL: u32 = 57;
const MODE_LOCAL_SIZE: u32 = 17;
const DECORATION_OFFSET: u32 = 35;
const HEADER_WORDS: usize = 5;

/// Yields (opcode, operands) for each instruction.
fn instructions(words: &[u32]) -> impl Iterator<Item = (u32, &[u32])> {
    let mut at = HEADER_WORDS.min(words.len());
    std::iter::from_fn(move || {
        let first = *words.get(at)?;
        let count = (first >> 16) as usize;
        if count == 0 || at + count > words.len() {
            return None;
        }
        let operands = &words[at + 1..at + count];
        at += count;
        Some((first & 0xffff, operands))
    })
}

fn literal_string(words: &[u32]) -> String {
    let bytes: Vec<u8> = words
        .iter()
        .flat_map(|w| w.to_le_bytes())
        .take_while(|&b| b != 0)
        .collect();
    String::from_utf8_lossy(&bytes).into_owned()
}

pub fn local_size(words: &[u32]) -> Option<[u32; 3]> {
    instructions(words).find_map(|(op, args)| {
        (op == OP_EXECUTION_MODE && args.len() >= 5 && args[1] == MODE_LOCAL_SIZE)
            .then(|| [args[2], args[3], args[4]])
    })
}

/// Member names and byte offsets of the struct type called `type_name`, in member order.
pub fn struct_offsets(words: &[u32], type_name: &str) -> Option<Vec<(String, u32)>> {
    let id = instructions(words).find_map(|(op, args)| {
        (op == OP_NAME && args.len() >= 2 && literal_string(&args[1..]) == type_name)
            .then(|| args[0])
    })?;
    let mut names = std::collections::BTreeMap::new();
    let mut offsets = std::collections::BTreeMap::new();
    for (op, args) in instructions(words) {
        if args.first() != Some(&id) || args.len() < 3 {
            continue;
        }
        if op == OP_MEMBER_NAME {
            names.insert(args[1], literal_string(&args[2..]));
        } else if op == OP_MEMBER_DECORATE && args[2] == DECORATION_OFFSET && args.len() >= 4 {
            offsets.insert(args[1], args[3]);
        }
    }
    Some(
        offsets
            .into_iter()
            .map(|(member, offset)| (names.get(&member).cloned().unwrap_or_default(), offset))
            .collect(),
    )
}

/// How many copies of the functions whose debug name starts with `name` (glslang names a
/// function `name(` followed by its parameter types) the entry points hold once every call is
/// inlined: the number of call paths from an entry point to them. `None` without such a
/// function or where calls recurse (which GLSL forbids).
pub fn inlined_copies(words: &[u32], name: &str) -> Option<u64> {
    use std::collections::HashMap;
    let mut targets = Vec::new();
    let mut entries = Vec::new();
    let mut calls: HashMap<u32, Vec<u32>> = HashMap::new();
    let mut current = None;
    for (op, args) in instructions(words) {
        match op {
            OP_NAME if args.len() >= 2 && literal_string(&args[1..]).starts_with(name) => {
                let full = literal_string(&args[1..]);
                if full[name.len()..].starts_with('(') {
                    targets.push(args[0]);
                }
            }
            OP_ENTRY_POINT if args.len() >= 2 => entries.push(args[1]),
            OP_FUNCTION if args.len() >= 2 => current = Some(args[1]),
            OP_FUNCTION_END => current = None,
            OP_FUNCTION_CALL if args.len() >= 3 => {
                calls.entry(current?).or_default().push(args[2]);
            }
            _ => {}
        }
    }
    if targets.is_empty() {
        return None;
    }
    fn copies(
        f: u32,
        targets: &[u32],
        calls: &std::collections::HashMap<u32, Vec<u32>>,
        memo: &mut std::collections::HashMap<u32, Option<u64>>,
        depth: usize,
    ) -> Option<u64> {
        if targets.contains(&f) {
            return Some(1);
        }
        if let Some(known) = memo.get(&f) {
            return *known;
        }
        if depth > calls.len() {
            return None; // deeper than there are functions: a cycle
        }
        let mut sum = 0u64;
        for &callee in calls.get(&f).map(Vec::as_slice).unwrap_or_default() {
            sum = sum.checked_add(copies(callee, targets, calls, memo, depth + 1)?)?;
        }
        memo.insert(f, Some(sum));
        Some(sum)
    }
    let mut memo = HashMap::new();
    entries.iter().try_fold(0u64, |total, &entry| {
        total.checked_add(copies(entry, &targets, &calls, &mut memo, 0)?)
    })
}
