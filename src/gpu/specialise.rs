//! The kernel specialised for one variant on the host: its overrides made
//! constants (naga's `process_overrides`), then every branch and call they
//! decide folded away and every function no longer called dropped, so that
//! the driver receives only the code the variant can reach.
//!
//! Why: lavapipe (Mesa 22.3) inlines and lowers the whole module before its
//! own constant folding removes a branch, so every variant paid for the
//! whole kernel: measured, the seed's sphere-only Whitted variant compiled
//! as long as the Cornell box's path tracer with glass (3.8 s each, debug
//! build), 70% of it in lavapipe's own passes, not in LLVM.
//!
//! The folding is exact: it evaluates only comparisons and logic of
//! literals, takes the branch a literal condition picks, removes calls of
//! functions whose body returns a literal before anything else, and drops
//! statements after a `return`, `break` or `continue` in the same block.
//! What it cannot decide it leaves to the driver.

use std::collections::HashMap;

use naga::{
    BinaryOperator, Block, Expression, Function, Handle, Literal, Module, Statement, UnaryOperator,
};

/// `module` with `constants` (override name -> value) applied, holding
/// only the entry point `entry`, and if `fold_branches`, the code they rule
/// out removed. `info` is `module`'s validation.
pub fn specialise(
    module: &Module,
    info: &naga::valid::ModuleInfo,
    entry: &str,
    constants: &[(&str, f64)],
    fold_branches: bool,
) -> Result<Module, String> {
    let values: naga::back::PipelineConstants =
        constants.iter().map(|&(k, v)| (k.to_string(), v)).collect();
    let (processed, _) = naga::back::pipeline_constants::process_overrides(
        module,
        info,
        Some((naga::ShaderStage::Compute, entry)),
        &values,
    )
    .map_err(|e| format!("specialising {entry}: {e}"))?;
    let mut module = processed.into_owned();
    if fold_branches {
        fold(&mut module);
    }
    naga::compact::compact(&mut module, naga::compact::KeepUnused::No);
    Ok(module)
}

/// Folds every function of `module` (callees before callers, as the arena
/// orders them), until nothing changes.
fn fold(module: &mut Module) {
    let mut constant_functions: HashMap<Handle<Function>, Literal> = HashMap::new();
    loop {
        let mut changed = false;
        let handles: Vec<Handle<Function>> = module.functions.iter().map(|(h, _)| h).collect();
        for h in handles {
            let mut function = std::mem::take(&mut module.functions[h]);
            changed |= fold_function(module, &constant_functions, &mut function);
            if let Some(l) = returned_literal(module, &function) {
                changed |= constant_functions.insert(h, l).is_none();
            }
            module.functions[h] = function;
        }
        for i in 0..module.entry_points.len() {
            let mut function = std::mem::take(&mut module.entry_points[i].function);
            changed |= fold_function(module, &constant_functions, &mut function);
            module.entry_points[i].function = function;
        }
        if !changed {
            return;
        }
    }
}

/// Folds one function's expressions and statements; whether anything
/// changed.
fn fold_function(
    module: &Module,
    constant_functions: &HashMap<Handle<Function>, Literal>,
    function: &mut Function,
) -> bool {
    let mut changed = false;
    let handles: Vec<Handle<Expression>> = function.expressions.iter().map(|(h, _)| h).collect();
    for h in handles {
        let folded = match function.expressions[h] {
            Expression::CallResult(f) => constant_functions.get(&f).copied(),
            ref e => fold_expression(module, &function.expressions, e),
        };
        if let Some(l) = folded {
            function.expressions[h] = Expression::Literal(l);
            changed = true;
        }
    }
    let body = std::mem::take(&mut function.body);
    let (body, body_changed) = fold_block(module, constant_functions, &function.expressions, body);
    function.body = body;
    zero_orphaned_results(module, function);
    let forwarded = forward_decided_logic(module, function);
    changed || body_changed || forwarded
}

/// The result of a short-circuit `&&` or `||` once its branch is decided:
/// naga's front end writes `a && b` as an unnamed boolean variable stored
/// in both arms of `if a`; with one arm left, and a literal stored there,
/// every load of the variable is that literal. Whether any load changed.
fn forward_decided_logic(module: &Module, function: &mut Function) -> bool {
    let mut stored: HashMap<Handle<naga::LocalVariable>, Vec<Handle<Expression>>> = HashMap::new();
    each_statement(&function.body, &mut |s| {
        if let Statement::Store { pointer, value } = *s {
            if let Expression::LocalVariable(v) = function.expressions[pointer] {
                stored.entry(v).or_default().push(value);
            }
        }
    });
    let decided: HashMap<Handle<naga::LocalVariable>, Literal> = stored
        .into_iter()
        .filter(|(v, _)| {
            let local = &function.local_variables[*v];
            local.name.is_none()
                && local.init.is_none()
                && matches!(
                    module.types[local.ty].inner,
                    naga::TypeInner::Scalar(naga::Scalar::BOOL)
                )
        })
        .filter_map(|(v, values)| match values[..] {
            [value] => Some((v, literal(module, &function.expressions, value)?)),
            _ => None,
        })
        .collect();
    let loads: Vec<(Handle<Expression>, Literal)> = function
        .expressions
        .iter()
        .filter_map(|(h, e)| match *e {
            Expression::Load { pointer } => match function.expressions[pointer] {
                Expression::LocalVariable(v) => Some((h, *decided.get(&v)?)),
                _ => None,
            },
            _ => None,
        })
        .collect();
    let changed = !loads.is_empty();
    for (h, l) in loads {
        function.expressions[h] = Expression::Literal(l);
    }
    changed
}

/// Every call or atomic result whose statement was in a branch taken away
/// becomes a zero value of its type: the validator wants each such result
/// visited by its statement, and nothing reads these.
fn zero_orphaned_results(module: &Module, function: &mut Function) {
    let mut kept = std::collections::HashSet::new();
    each_statement(&function.body, &mut |s| match *s {
        Statement::Call {
            result: Some(r), ..
        }
        | Statement::Atomic {
            result: Some(r), ..
        } => {
            kept.insert(r);
        }
        _ => {}
    });
    let orphans: Vec<(Handle<Expression>, Handle<naga::Type>)> = function
        .expressions
        .iter()
        .filter(|(h, _)| !kept.contains(h))
        .filter_map(|(h, e)| match *e {
            Expression::CallResult(f) => Some((h, module.functions[f].result.as_ref()?.ty)),
            Expression::AtomicResult { ty, .. } => Some((h, ty)),
            _ => None,
        })
        .collect();
    for (h, ty) in orphans {
        function.expressions[h] = Expression::ZeroValue(ty);
    }
}

/// Calls `f` with every statement of `block`, nested ones included.
fn each_statement(block: &Block, f: &mut impl FnMut(&Statement)) {
    for s in block.iter() {
        f(s);
        match s {
            Statement::Block(b) => each_statement(b, f),
            Statement::If { accept, reject, .. } => {
                each_statement(accept, f);
                each_statement(reject, f);
            }
            Statement::Switch { cases, .. } => {
                cases.iter().for_each(|c| each_statement(&c.body, f))
            }
            Statement::Loop {
                body, continuing, ..
            } => {
                each_statement(body, f);
                each_statement(continuing, f);
            }
            _ => {}
        }
    }
}

/// The literal `h` is: a literal, or a constant initialised with one.
fn literal(
    module: &Module,
    expressions: &naga::Arena<Expression>,
    h: Handle<Expression>,
) -> Option<Literal> {
    match expressions[h] {
        Expression::Literal(l) => Some(l),
        Expression::Constant(c) => match module.global_expressions[module.constants[c].init] {
            Expression::Literal(l) => Some(l),
            _ => None,
        },
        _ => None,
    }
}

/// The literal `e` evaluates to, where its operands are literals (or, for
/// `&&` and `||`, where one operand decides).
fn fold_expression(
    module: &Module,
    expressions: &naga::Arena<Expression>,
    e: &Expression,
) -> Option<Literal> {
    match *e {
        Expression::Unary {
            op: UnaryOperator::LogicalNot,
            expr,
        } => match literal(module, expressions, expr)? {
            Literal::Bool(b) => Some(Literal::Bool(!b)),
            _ => None,
        },
        Expression::Binary { op, left, right } => {
            let (a, b) = (
                literal(module, expressions, left),
                literal(module, expressions, right),
            );
            match (op, a, b) {
                (BinaryOperator::LogicalAnd, Some(Literal::Bool(false)), _)
                | (BinaryOperator::LogicalAnd, _, Some(Literal::Bool(false))) => {
                    Some(Literal::Bool(false))
                }
                (BinaryOperator::LogicalOr, Some(Literal::Bool(true)), _)
                | (BinaryOperator::LogicalOr, _, Some(Literal::Bool(true))) => {
                    Some(Literal::Bool(true))
                }
                (_, Some(a), Some(b)) => compare(op, a, b),
                _ => None,
            }
        }
        _ => None,
    }
}

/// `a op b` for two literals of the same integer or boolean type.
fn compare(op: BinaryOperator, a: Literal, b: Literal) -> Option<Literal> {
    use std::cmp::Ordering;
    let ordering = match (a, b) {
        (Literal::U32(x), Literal::U32(y)) => x.cmp(&y),
        (Literal::I32(x), Literal::I32(y)) => x.cmp(&y),
        (Literal::Bool(x), Literal::Bool(y)) => match op {
            BinaryOperator::LogicalAnd => return Some(Literal::Bool(x && y)),
            BinaryOperator::LogicalOr => return Some(Literal::Bool(x || y)),
            _ => x.cmp(&y),
        },
        _ => return None,
    };
    let value = match op {
        BinaryOperator::Equal => ordering == Ordering::Equal,
        BinaryOperator::NotEqual => ordering != Ordering::Equal,
        BinaryOperator::Less => ordering == Ordering::Less,
        BinaryOperator::LessEqual => ordering != Ordering::Greater,
        BinaryOperator::Greater => ordering == Ordering::Greater,
        BinaryOperator::GreaterEqual => ordering != Ordering::Less,
        _ => return None,
    };
    Some(Literal::Bool(value))
}

/// `block` with literal conditions' branches taken, calls of constant
/// functions removed, folded expressions taken out of its `Emit`s, and
/// nothing after a statement that leaves it; whether anything changed.
fn fold_block(
    module: &Module,
    constant_functions: &HashMap<Handle<Function>, Literal>,
    expressions: &naga::Arena<Expression>,
    block: Block,
) -> (Block, bool) {
    let mut out = Block::with_capacity(block.len());
    let mut changed = false;
    let recurse = |b: Block, changed: &mut bool| {
        let (b, c) = fold_block(module, constant_functions, expressions, b);
        *changed |= c;
        b
    };
    for (statement, span) in block.span_into_iter() {
        let statement = match statement {
            Statement::Emit(range) => {
                let mut run: Option<(Handle<Expression>, Handle<Expression>)> = None;
                for h in range {
                    if expressions[h].needs_pre_emit() {
                        changed = true;
                        if let Some((first, last)) = run.take() {
                            out.push(
                                Statement::Emit(naga::Range::new_from_bounds(first, last)),
                                span,
                            );
                        }
                    } else {
                        run = Some(run.map_or((h, h), |(first, _)| (first, h)));
                    }
                }
                match run {
                    Some((first, last)) => {
                        Statement::Emit(naga::Range::new_from_bounds(first, last))
                    }
                    None => continue,
                }
            }
            Statement::If {
                condition,
                accept,
                reject,
            } => match literal(module, expressions, condition) {
                Some(Literal::Bool(taken)) => {
                    changed = true;
                    Statement::Block(recurse(if taken { accept } else { reject }, &mut changed))
                }
                _ => Statement::If {
                    condition,
                    accept: recurse(accept, &mut changed),
                    reject: recurse(reject, &mut changed),
                },
            },
            Statement::Call {
                function,
                result: Some(_),
                ..
            } if constant_functions.contains_key(&function) => {
                changed = true;
                continue;
            }
            Statement::Block(b) => Statement::Block(recurse(b, &mut changed)),
            Statement::Switch { selector, cases } => Statement::Switch {
                selector,
                cases: cases
                    .into_iter()
                    .map(|mut case| {
                        case.body = recurse(std::mem::take(&mut case.body), &mut changed);
                        case
                    })
                    .collect(),
            },
            Statement::Loop {
                body,
                continuing,
                break_if,
            } => Statement::Loop {
                body: recurse(body, &mut changed),
                continuing: recurse(continuing, &mut changed),
                break_if,
            },
            other => other,
        };
        let leaves = leaves_block(&statement);
        out.push(statement, span);
        if leaves {
            // What follows is never reached.
            break;
        }
    }
    (out, changed)
}

/// Whether `statement` always leaves the block it is in.
fn leaves_block(statement: &Statement) -> bool {
    match statement {
        Statement::Return { .. } | Statement::Break | Statement::Continue | Statement::Kill => true,
        Statement::Block(b) => b.last().is_some_and(leaves_block),
        _ => false,
    }
}

/// The literal `function` returns before doing anything else, if it does.
fn returned_literal(module: &Module, function: &Function) -> Option<Literal> {
    fn first(block: &Block) -> Option<&Statement> {
        for s in block.iter() {
            match s {
                Statement::Emit(_) => continue,
                Statement::Block(b) => match first(b) {
                    Some(s) => return Some(s),
                    None => continue,
                },
                other => return Some(other),
            }
        }
        None
    }
    match first(&function.body)? {
        Statement::Return { value: Some(h) } => literal(module, &function.expressions, *h),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::bindings;
    use crate::gpu::kernel_variant::{KernelVariant, Walk};
    use crate::kdtree::Traversal;

    fn validate(module: &Module) -> Result<naga::valid::ModuleInfo, String> {
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::all(),
        )
        .validate(module)
        .map_err(|e| format!("{e:?}"))
    }

    fn parsed(source: &str) -> (Module, naga::valid::ModuleInfo) {
        let module = naga::front::wgsl::parse_str(source).unwrap_or_else(|e| panic!("{e}"));
        let info = validate(&module).unwrap();
        (module, info)
    }

    fn function_names(module: &Module) -> Vec<String> {
        module
            .functions
            .iter()
            .filter_map(|(_, f)| f.name.clone())
            .collect()
    }

    /// Whether `block` holds an `if` anywhere.
    fn has_if(block: &Block) -> bool {
        block.iter().any(|s| match s {
            Statement::If { .. } => true,
            Statement::Block(b) => has_if(b),
            Statement::Loop { body, .. } => has_if(body),
            _ => false,
        })
    }

    const SMALL: &str = "
        override FAST: bool = false;
        override MODE: u32 = 0u;
        @group(0) @binding(0) var<storage, read_write> out: array<u32>;
        fn mode() -> u32 {
            if (MODE != 0u) {
                return MODE;
            }
            return out[1];
        }
        fn slow_path(i: u32) -> u32 {
            return out[i] * 3u + 1u;
        }
        @compute @workgroup_size(1)
        fn main(@builtin(global_invocation_id) id: vec3<u32>) {
            if (!FAST && mode() == 2u) {
                out[0] = slow_path(id.x);
                return;
            }
            out[0] = 7u;
            out[2] = 9u;
        }
    ";

    /// The override values decide every branch: the branch they pick is
    /// kept, the other and every function only it called are gone, and a
    /// function returning a constant is no longer called.
    #[test]
    fn literal_branches_are_taken_and_unreached_functions_dropped() {
        let (module, info) = parsed(SMALL);
        let fast = specialise(
            &module,
            &info,
            "main",
            &[("FAST", 1.0), ("MODE", 2.0)],
            true,
        )
        .unwrap();
        validate(&fast).unwrap();
        assert!(
            function_names(&fast).is_empty(),
            "{:?}",
            function_names(&fast)
        );
        assert!(!has_if(&fast.entry_points[0].function.body));

        let slow = specialise(
            &module,
            &info,
            "main",
            &[("FAST", 0.0), ("MODE", 2.0)],
            true,
        )
        .unwrap();
        validate(&slow).unwrap();
        assert_eq!(function_names(&slow), ["slow_path"]);
        // `!FAST && mode() == 2u` is true: the branch is taken, unconditioned.
        assert!(!has_if(&slow.entry_points[0].function.body));

        // MODE 0 leaves mode() reading the buffer: nothing to decide.
        let open = specialise(
            &module,
            &info,
            "main",
            &[("FAST", 0.0), ("MODE", 0.0)],
            true,
        )
        .unwrap();
        validate(&open).unwrap();
        assert_eq!(function_names(&open), ["mode", "slow_path"]);
        assert!(has_if(&open.entry_points[0].function.body));
    }

    /// Every kind of variant the renderer makes, for both entry points that
    /// go through it, folds to a module naga validates.
    #[test]
    fn every_kind_of_variant_folds_to_a_valid_module() {
        let walks = [
            Walk::FromParams,
            Walk::Brute,
            Walk::Kdtree(Traversal::Restart),
            Walk::Kdtree(Traversal::Ropes),
            Walk::Kdtree(Traversal::ShortStack),
        ];
        for entry in [bindings::RENDER_TILE, bindings::INSPECT_PIXEL] {
            let kernel = crate::gpu::shaders::kernel_ir(entry, bindings::UNSPLIT, &[]).unwrap();
            for (i, walk) in walks.into_iter().enumerate() {
                for bits in 0..16u32 {
                    let on = |b: u32| bits & (1 << b) != 0;
                    let variant = KernelVariant {
                        walk,
                        spheres: on(0),
                        triangles: !on(0) || on(1),
                        smooth_triangles: on(1),
                        glass: on(2),
                        textures: on(3),
                        alpha_test: on(3) && i % 2 == 0,
                        spot_or_directional_lights: on(2),
                        count_costs: on(1) != on(3),
                        integrator: [
                            crate::layout::INTEGRATOR_WHITTED,
                            crate::layout::INTEGRATOR_PATH,
                            crate::gpu::kernel_variant::FROM_PARAMS,
                        ][(bits % 3) as usize],
                        radiance_output: on(2),
                        feature_output: on(2) && on(0),
                        split_scene: i == 0,
                    };
                    let module =
                        specialise(&kernel.0, &kernel.1, entry.name, &variant.constants(), true)
                            .unwrap_or_else(|e| panic!("{variant:?}: {e}"));
                    validate(&module).unwrap_or_else(|e| panic!("{} {variant:?}: {e}", entry.name));
                }
            }
        }
    }

    /// A variant for spheres under the Whitted integrator holds neither the
    /// triangle test nor the path tracer; the general variant, which
    /// decides at run time, holds both.
    #[test]
    fn a_variant_holds_only_the_code_it_can_reach() {
        let kernel =
            crate::gpu::shaders::kernel_ir(bindings::RENDER_TILE, bindings::UNSPLIT, &[]).unwrap();
        let names = |v: KernelVariant| {
            let m = specialise(&kernel.0, &kernel.1, "render_tile", &v.constants(), true).unwrap();
            function_names(&m)
        };
        let general = names(KernelVariant {
            radiance_output: true,
            ..KernelVariant::GENERAL
        });
        let spheres = names(KernelVariant {
            walk: Walk::Kdtree(Traversal::ShortStack),
            spheres: true,
            triangles: false,
            smooth_triangles: false,
            glass: false,
            textures: false,
            alpha_test: false,
            spot_or_directional_lights: false,
            count_costs: false,
            integrator: crate::layout::INTEGRATOR_WHITTED,
            radiance_output: false,
            feature_output: false,
            split_scene: false,
        });
        for name in [
            "intersect_triangle",
            "path_trace_sample",
            "intersect_sphere",
        ] {
            assert!(general.iter().any(|n| n == name), "general: no {name}");
        }
        assert!(spheres.iter().any(|n| n == "intersect_sphere"));
        for name in ["intersect_triangle", "path_trace_sample"] {
            assert!(!spheres.iter().any(|n| n == name), "spheres: {name} kept");
        }
        assert!(
            spheres.len() * 2 < general.len(),
            "{} of {} functions kept",
            spheres.len(),
            general.len()
        );
    }
}
