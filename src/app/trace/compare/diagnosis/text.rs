//! What the diagnosis says: the mistake of the gallery the student's
//! numbers come from, with its line as written and as the handout has it
//! and its section of `docs/mistakes.md`; or that none does, and the hint
//! that holds; each after the quantities that differ only because their
//! inputs do.

use masssprings::sim::mistakes::Mistake;

/// The diagnosis of a comparison that differs.
#[derive(Debug, Clone, PartialEq)]
pub struct Diagnosis {
    /// The mistake of the gallery whose numbers the student's are.
    pub mistake: Option<Mistake>,
    /// What went wrong, in a sentence or two.
    pub text: String,
}

impl Diagnosis {
    /// The student's `at` is what `mistake` makes of their inputs.
    pub fn named(mistake: Mistake, at: &str) -> Diagnosis {
        let entry = mistake.entry();
        let whose = match mistake {
            Mistake::VelocityLost => format!("your {at} is your U_cur"),
            _ => format!("your {at} is what it makes of your own inputs"),
        };
        Diagnosis {
            mistake: Some(mistake),
            text: format!(
                "the mistake {name}: `{wrong}` where the handout has `{right}` ({whose}; \
                 docs/mistakes.md#{name})",
                name = entry.name,
                wrong = entry.wrong,
                right = entry.right,
            ),
        }
    }

    /// No mistake of the gallery makes the student's `at`.
    pub fn unexplained(at: &str, hint: &str) -> Diagnosis {
        Diagnosis {
            mistake: None,
            text: format!("no mistake of the gallery makes your {at} from your own inputs; {hint}"),
        }
    }
}

/// What the walk found before the quantity it diagnoses: the state's
/// quantities that are the student's own steps' (not ours, and no mistake
/// of the loop), and the quantities that are the handout's formulas of the
/// student's own inputs.
#[derive(Debug, Default)]
pub struct Earlier {
    pub state: Vec<String>,
    pub explained: Vec<String>,
}

impl Earlier {
    /// `diagnosis`, after what the walk found before it.
    pub fn before(&self, mut diagnosis: Diagnosis) -> Diagnosis {
        let mut said = Vec::new();
        if !self.state.is_empty() {
            said.push(format!(
                "your {} {} your own steps' from rest, not ours, and not by a mistake of the \
                 loop that the gallery knows",
                self.state.join(" and "),
                plural(&self.state, "is", "are"),
            ));
        }
        if !self.explained.is_empty() {
            said.push(format!(
                "{} {} only because {} (the handout's formulas make your numbers of your own \
                 inputs)",
                self.explained.join(", "),
                plural(&self.explained, "differs", "differ"),
                plural(&self.explained, "its inputs do", "their inputs do"),
            ));
        }
        if !said.is_empty() {
            diagnosis.text = format!("{}; then {}", said.join("; "), diagnosis.text);
        }
        diagnosis
    }

    /// When every quantity that differs is the handout's formula of the
    /// student's own inputs.
    pub fn all_explained(&self) -> Diagnosis {
        let text = match self.state.is_empty() {
            false => format!(
                "your {} {} your own steps' from rest, not ours, and your step from there is \
                 the handout's: your loop over steps (U_prev ← U_cur, U_cur ← U_next) or your \
                 forces in the steps before differ from the handout's",
                self.state.join(" and "),
                plural(&self.state, "is", "are"),
            ),
            true => format!(
                "{} {} within the tolerance of the handout's formulas of your own inputs: the \
                 small differences of those inputs add up",
                self.explained.join(", "),
                plural(&self.explained, "is", "are"),
            ),
        };
        Diagnosis {
            mistake: None,
            text,
        }
    }
}

/// `one` or `many`, by the length of `list`.
fn plural<'a>(list: &[String], one: &'a str, many: &'a str) -> &'a str {
    match list.len() {
        1 => one,
        _ => many,
    }
}
