//! Tests of `sample_data`.

use super::*;

/// A stream of `len` bytes that counts how many were asked for.
struct Counted {
    left: usize,
}

impl Read for Counted {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = buf.len().min(self.left);
        buf[..n].fill(7);
        self.left -= n;
        Ok(n)
    }
}

#[test]
fn a_stream_shorter_than_promised_costs_only_its_data() {
    // 1 TiB promised, 10 bytes there: allocating the promise up front would abort.
    let got = read_values::<u8>(&mut Counted { left: 10 }, 1 << 40, Supply::Stream).unwrap();
    assert_eq!(got, Err(10));
    let got = read_values::<f32>(&mut Counted { left: 4 << 20 }, 1 << 38, Supply::Stream);
    assert_eq!(got.unwrap(), Err(4 << 20));
}

#[test]
fn streams_and_checked_files_read_the_same() {
    let count = 3 * FIRST_STREAM_CHUNK / 2 + 5;
    for supply in [Supply::Checked, Supply::Stream] {
        let v = read_values::<u16>(
            &mut Counted {
                left: 2 * count + 9,
            },
            count,
            supply,
        )
        .unwrap()
        .expect("complete");
        assert_eq!(v.len(), count, "{supply:?}");
        assert!(v.iter().all(|&x| x == 0x0707), "{supply:?}");
    }
    let empty = read_values::<f32>(&mut Counted { left: 0 }, 0, Supply::Stream).unwrap();
    assert_eq!(empty, Ok(Vec::new()));
}

#[test]
fn read_samples_refuses_counts_over_the_limit_and_short_data() {
    let path = Path::new("big.nii.gz");
    let count = (crate::input::MAX_SAMPLE_BYTES / 4 + 1) as usize;
    let mut input = Counted { left: 100 };
    let err = read_samples(
        &mut input,
        count,
        SourceType::F32,
        Endian::Little,
        Supply::Checked,
        path,
    )
    .expect_err("over the limit");
    assert!(err.to_string().contains("big.nii.gz"), "{err}");
    assert_eq!(input.left, 100, "nothing may be read before the check");

    let err = read_samples(
        &mut Counted { left: 5 },
        4,
        SourceType::I16,
        Endian::Big,
        Supply::Stream,
        path,
    )
    .expect_err("short");
    assert!(
        matches!(
            err,
            DataError::SizeMismatch {
                expected_bytes: 8,
                found_bytes: 5,
                ..
            }
        ),
        "{err}"
    );
}

#[test]
fn skip_stops_at_the_end() {
    assert_eq!(skip(&mut Counted { left: 20_000 }, 9_000).unwrap(), 9_000);
    assert_eq!(skip(&mut Counted { left: 20 }, u64::MAX).unwrap(), 20);
}
