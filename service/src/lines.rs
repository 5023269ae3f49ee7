//! Reading newline-terminated lines with a length limit.
//!
//! A line longer than the limit is consumed and discarded up to its newline without being
//! kept in memory, so a hostile or broken peer can neither exhaust memory nor desynchronise
//! the conversation: the next line is read normally.

use std::io::{self, BufRead};

/// What [`read_line`] found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LineRead {
    /// A line (without its `\n` or `\r\n`) is in the buffer.
    Line,
    /// A line longer than the limit was read and discarded; the buffer is empty.
    TooLong,
}

/// Reads the next line into `line` (cleared first). The last line may lack its newline.
/// Returns `None` at the end of the input.
pub fn read_line<R: BufRead + ?Sized>(
    reader: &mut R,
    limit: usize,
    line: &mut Vec<u8>,
) -> io::Result<Option<LineRead>> {
    line.clear();
    let mut read_any = false;
    let mut too_long = false;
    loop {
        let available = match reader.fill_buf() {
            Ok(bytes) => bytes,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(e),
        };
        if available.is_empty() {
            return Ok(read_any.then_some(finish(line, too_long)));
        }
        read_any = true;
        let newline = available.iter().position(|&b| b == b'\n');
        let chunk = &available[..newline.unwrap_or(available.len())];
        if !too_long {
            if line.len() + chunk.len() > limit {
                too_long = true;
                line.clear();
            } else {
                line.extend_from_slice(chunk);
            }
        }
        let used = chunk.len() + usize::from(newline.is_some());
        reader.consume(used);
        if newline.is_some() {
            return Ok(Some(finish(line, too_long)));
        }
    }
}

fn finish(line: &mut Vec<u8>, too_long: bool) -> LineRead {
    if too_long {
        LineRead::TooLong
    } else {
        if line.last() == Some(&b'\r') {
            line.pop();
        }
        LineRead::Line
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::BufReader;

    fn all_lines(input: &[u8], limit: usize, capacity: usize) -> Vec<Result<String, ()>> {
        let mut reader = BufReader::with_capacity(capacity, input);
        let mut line = Vec::new();
        let mut out = Vec::new();
        while let Some(read) = read_line(&mut reader, limit, &mut line).unwrap() {
            out.push(match read {
                LineRead::Line => Ok(String::from_utf8(line.clone()).unwrap()),
                LineRead::TooLong => Err(()),
            });
        }
        out
    }

    #[test]
    fn lines_are_split_and_crlf_trimmed() {
        let got = all_lines(b"ab\r\n\ncd", 10, 3);
        assert_eq!(
            got,
            vec![Ok("ab".into()), Ok(String::new()), Ok("cd".into())]
        );
    }

    #[test]
    fn an_oversize_line_is_skipped_and_the_next_is_read() {
        // The limit is 4 bytes; the buffer is smaller than the long line, so it arrives in
        // pieces and is dropped piece by piece.
        let got = all_lines(b"0123456789\nok\n12345", 4, 3);
        assert_eq!(got, vec![Err(()), Ok("ok".into()), Err(())]);
        assert_eq!(all_lines(b"1234\n", 4, 2), vec![Ok("1234".into())]);
    }

    #[test]
    fn empty_input_has_no_lines() {
        assert!(all_lines(b"", 4, 2).is_empty());
    }
}
