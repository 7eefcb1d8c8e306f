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

    /// `earlier` differ only as their inputs do.
    pub fn after(mut self, earlier: &[String]) -> Diagnosis {
        let (verb, whose) = match earlier.len() {
            0 => return self,
            1 => ("differs", "its inputs do"),
            _ => ("differ", "their inputs do"),
        };
        self.text = format!(
            "{} {verb} only because {whose} (the handout's formulas make your numbers of \
             your own inputs); then {}",
            earlier.join(", "),
            self.text
        );
        self
    }
}
