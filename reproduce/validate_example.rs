//! The example external engine of VALIDATION.md: the reference engines behind
//! the external-program contract. `validate --candidate cmd:'PATH/validate-example'`
//! must pass; an engine in another language does what this does.
//!
//! Protocol: called as `validate-example run --plan -`, it reads one JSON
//! RunPlan on stdin and prints one JSON Sample per line on stdout (the
//! pipe); called as `validate-example hopper --plan -`, one JSON HopperPlan,
//! and prints the lines of its action (the hopper). With `--mutant NAME`
//! first, it serves that mutant of the catalogue instead (a wrong engine
//! behind the contract, for the tests).

use granular_automata::hopper::engine::Reference as ReferenceHopper;
use granular_automata::pipe::engine::Reference;
use granular_automata::validate::mutants::Mutant;
use granular_automata::validate::{candidate, external_hopper};

/// How to call it (printed by `--help`, and with a usage error).
const USAGE: &str = "usage: validate-example [--mutant NAME] run --plan - (a RunPlan as JSON on stdin) or validate-example [--mutant NAME] hopper --plan - (a HopperPlan)";

granular_automata::main_of!(body);

fn body() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    let (input, output) = (&mut std::io::stdin(), &mut out);
    match args.iter().map(String::as_str).collect::<Vec<_>>()[..] {
        ["run", "--plan", "-"] => candidate::serve(Reference, input, output)?,
        ["hopper", "--plan", "-"] => external_hopper::serve(&ReferenceHopper, input, output)?,
        ["--mutant", name, "run", "--plan", "-"] => {
            candidate::serve(name.parse::<Mutant>()?, input, output)?
        }
        ["--mutant", name, "hopper", "--plan", "-"] => {
            external_hopper::serve(&name.parse::<Mutant>()?, input, output)?
        }
        ["--help"] | ["-h"] => println!("{USAGE}"),
        _ => {
            return Err(granular_automata::Error::new(
                granular_automata::ErrorKind::InvalidParameter,
                format!("{USAGE}; got {args:?}"),
            )
            .into())
        }
    }
    Ok(())
}
