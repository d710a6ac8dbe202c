//! Small pieces of English for messages: a count with its noun in the right number.

/// `1 pass`, `2 passes`, `0 passes`.
pub fn count(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// A pass table's size as a message says it: `8 rough passes and 1 finishing pass`.
pub fn rough_and_finishing(rough: usize, finishing: usize) -> String {
    let mut s = String::with_capacity(40);
    push_rough_and_finishing(&mut s, rough, finishing);
    s
}

/// [`rough_and_finishing`] appended to `s` (the expansion's comment on every cycle: no
/// allocation of its own).
pub fn push_rough_and_finishing(s: &mut String, rough: usize, finishing: usize) {
    push_count(s, rough, "rough pass", "rough passes");
    s.push_str(" and ");
    push_count(s, finishing, "finishing pass", "finishing passes");
}

fn push_count(s: &mut String, n: usize, one: &str, many: &str) {
    push_decimal(s, n as u64);
    s.push(' ');
    s.push_str(if n == 1 { one } else { many });
}

/// `n` in decimal digits, appended.
pub(crate) fn push_decimal(s: &mut String, n: u64) {
    let mut digits = [0u8; 20];
    let mut at = digits.len();
    let mut v = n;
    loop {
        at -= 1;
        digits[at] = b'0' + (v % 10) as u8;
        v /= 10;
        if v == 0 {
            break;
        }
    }
    // ASCII digits.
    s.extend(digits[at..].iter().map(|&b| char::from(b)));
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
        assert_eq!(
            rough_and_finishing(0, 10),
            "0 rough passes and 10 finishing passes"
        );
        let mut s = String::new();
        push_decimal(&mut s, 0);
        s.push(' ');
        push_decimal(&mut s, u64::MAX);
        assert_eq!(s, format!("0 {}", u64::MAX));
    }
}
