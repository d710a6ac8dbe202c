//! Small pieces of English for messages: a count with its noun in the right number.

/// `1 pass`, `2 passes`, `0 passes`.
pub fn count(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// A pass table's size as a message says it: `8 rough passes and 1 finishing pass`.
pub fn rough_and_finishing(rough: usize, finishing: usize) -> String {
    format!(
        "{} and {}",
        count(rough, "rough pass", "rough passes"),
        count(finishing, "finishing pass", "finishing passes")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nouns_agree_with_their_counts() {
        assert_eq!(count(1, "tooth", "teeth"), "1 tooth");
        assert_eq!(count(0, "tooth", "teeth"), "0 teeth");
        assert_eq!(count(3, "start", "starts"), "3 starts");
        assert_eq!(
            rough_and_finishing(8, 1),
            "8 rough passes and 1 finishing pass"
        );
        assert_eq!(
            rough_and_finishing(1, 2),
            "1 rough pass and 2 finishing passes"
        );
    }
}
