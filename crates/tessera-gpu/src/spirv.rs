//! The little SPIR-V reflection Tessera needs: workgroup sizes (so dispatch helpers can turn
//! thread counts into group counts), struct member offsets (so a test can hold host structs
//! to the shader's layout) and how often a function is inlined (drivers inline every call, so
//! a shader's compile time grows with that count).

const OP_NAME: u32 = 5;
const OP_MEMBER_NAME: u32 = 6;
const OP_EXECUTION_MODE: u32 = 16;
const OP_MEMBER_DECORATE: u32 = 72;
const OP_ENTRY_POINT: u32 = 15;
const OP_TYPE_BOOL: u32 = 20;
const OP_TYPE_INT: u32 = 21;
const OP_TYPE_FLOAT: u32 = 22;
const OP_TYPE_VECTOR: u32 = 23;
const OP_TYPE_MATRIX: u32 = 24;
const OP_TYPE_ARRAY: u32 = 28;
const OP_TYPE_STRUCT: u32 = 30;
const OP_TYPE_POINTER: u32 = 32;
const OP_CONSTANT: u32 = 43;
const OP_VARIABLE: u32 = 59;
const STORAGE_PRIVATE: u32 = 6;
const STORAGE_FUNCTION: u32 = 7;
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
    // A struct a function also returns or takes by value has a second, undecorated copy of
    // the same name; the one laid out in memory is the one with offsets.
    let ids: Vec<u32> = instructions(words)
        .filter(|(op, args)| {
            *op == OP_NAME && args.len() >= 2 && literal_string(&args[1..]) == type_name
        })
        .map(|(_, args)| args[0])
        .collect();
    let layouts: Vec<Vec<(String, u32)>> =
        ids.iter().map(|&id| member_offsets(words, id)).collect();
    let first = layouts.first()?.clone();
    Some(layouts.into_iter().find(|l| !l.is_empty()).unwrap_or(first))
}

/// The (member name, offset) pairs of struct `id`, in member order; empty where the struct
/// has no offsets (a copy used only in functions).
fn member_offsets(words: &[u32], id: u32) -> Vec<(String, u32)> {
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
    offsets
        .into_iter()
        .map(|(member, offset)| (names.get(&member).cloned().unwrap_or_default(), offset))
        .collect()
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

/// Bytes of the variables each invocation holds on its own (`Function` and `Private` storage:
/// locals and globals without a buffer), counted without padding; arrays of unknown length or
/// types outside the plain scalars, vectors, matrices, arrays and structs count 0. Drivers
/// give each invocation this much scratch memory, and some fail hard when it is large.
pub fn invocation_local_bytes(words: &[u32]) -> u64 {
    use std::collections::HashMap;
    enum Type {
        Scalar(u64),
        Composite(u32, u64),
        Array(u32, u32),
        Struct(Vec<u32>),
        Pointer(u32),
    }
    let mut types: HashMap<u32, Type> = HashMap::new();
    let mut constants: HashMap<u32, u64> = HashMap::new();
    let mut variables = Vec::new();
    for (op, args) in instructions(words) {
        match (op, args) {
            (OP_TYPE_BOOL, [id, ..]) => {
                types.insert(*id, Type::Scalar(4));
            }
            (OP_TYPE_INT | OP_TYPE_FLOAT, [id, width, ..]) => {
                types.insert(*id, Type::Scalar(u64::from(*width) / 8));
            }
            (OP_TYPE_VECTOR | OP_TYPE_MATRIX, [id, element, count]) => {
                types.insert(*id, Type::Composite(*element, u64::from(*count)));
            }
            (OP_TYPE_ARRAY, [id, element, length]) => {
                types.insert(*id, Type::Array(*element, *length));
            }
            (OP_TYPE_STRUCT, [id, members @ ..]) => {
                types.insert(*id, Type::Struct(members.to_vec()));
            }
            (OP_TYPE_POINTER, [id, _, pointee]) => {
                types.insert(*id, Type::Pointer(*pointee));
            }
            (OP_CONSTANT, [_, id, value, ..]) => {
                constants.insert(*id, u64::from(*value));
            }
            (OP_VARIABLE, [pointer, _, storage, ..])
                if *storage == STORAGE_FUNCTION || *storage == STORAGE_PRIVATE =>
            {
                variables.push(*pointer);
            }
            _ => {}
        }
    }
    fn size(id: u32, types: &HashMap<u32, Type>, constants: &HashMap<u32, u64>, depth: u32) -> u64 {
        if depth > 64 {
            return 0;
        }
        let inner = |t| size(t, types, constants, depth + 1);
        match types.get(&id) {
            Some(Type::Scalar(bytes)) => *bytes,
            Some(Type::Composite(element, count)) => inner(*element).saturating_mul(*count),
            Some(Type::Array(element, length)) => {
                inner(*element).saturating_mul(constants.get(length).copied().unwrap_or(0))
            }
            Some(Type::Struct(members)) => members
                .iter()
                .map(|&m| inner(m))
                .fold(0, u64::saturating_add),
            Some(Type::Pointer(pointee)) => inner(*pointee),
            None => 0,
        }
    }
    variables
        .into_iter()
        .map(|pointer| size(pointer, &types, &constants, 0))
        .fold(0, u64::saturating_add)
}
