//! A minimal, deterministic PNG writer (indexed colour, 8 bits per pixel, zlib "stored" blocks)
//! and base64, for the raster cells of large heat maps ([`crate::Heatmap::to_svg`] above
//! [`crate::heatmap::RASTER_CELLS`] cells).
//!
//! The format follows the PNG specification (W3C, 2nd ed., 2003): signature, `IHDR` (colour
//! type 3), `PLTE`, one `IDAT` holding a zlib stream (RFC 1950) of uncompressed deflate blocks
//! (RFC 1951 §3.2.4, `BTYPE = 00`, ≤ 65 535 bytes each) over the scanlines (filter type 0), and
//! `IEND`; each chunk ends with its CRC-32 (ISO 3309 polynomial, reflected `0xEDB88320`). With one
//! byte per pixel a 600 × 450 raster is 270 kB before base64.

/// CRC-32 of `data` continued from `crc` (pass `0` to start).
fn crc32(crc: u32, data: &[u8]) -> u32 {
    let mut c = !crc;
    for &b in data {
        c ^= u32::from(b);
        for _ in 0..8 {
            c = if c & 1 != 0 {
                0xEDB8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
        }
    }
    !c
}

/// Adler-32 of `data` (RFC 1950).
fn adler32(data: &[u8]) -> u32 {
    const M: u32 = 65_521;
    let (mut a, mut b) = (1u32, 0u32);
    for chunk in data.chunks(5552) {
        for &x in chunk {
            a += u32::from(x);
            b += a;
        }
        a %= M;
        b %= M;
    }
    (b << 16) | a
}

fn chunk(out: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]) {
    // chunk lengths are bounded by the caller's raster size (< 2³¹)
    out.extend_from_slice(&(data.len() as u32).to_be_bytes());
    out.extend_from_slice(kind);
    out.extend_from_slice(data);
    let crc = crc32(crc32(0, kind), data);
    out.extend_from_slice(&crc.to_be_bytes());
}

/// An indexed-colour PNG of `width × height` pixels (`pixels[row * width + col]` indexes
/// `palette`, at most 256 entries). `None` for an empty image, a pixel count that does not match,
/// an empty or oversized palette, or an image above 2²⁴ pixels.
pub(crate) fn png_indexed(
    width: usize,
    height: usize,
    pixels: &[u8],
    palette: &[(u8, u8, u8)],
) -> Option<Vec<u8>> {
    if width == 0
        || height == 0
        || width.checked_mul(height)? != pixels.len()
        || pixels.len() > 1 << 24
        || palette.is_empty()
        || palette.len() > 256
        || pixels.iter().any(|&p| usize::from(p) >= palette.len())
    {
        return None;
    }
    let mut raw = Vec::with_capacity((width + 1) * height);
    for row in pixels.chunks(width) {
        raw.push(0); // filter type 0: none
        raw.extend_from_slice(row);
    }
    let mut z = vec![0x78, 0x01]; // zlib: deflate, 32 K window, no dictionary, check bits
    let blocks: Vec<&[u8]> = raw.chunks(65_535).collect();
    for (k, b) in blocks.iter().enumerate() {
        z.push(u8::from(k + 1 == blocks.len())); // BFINAL on the last, BTYPE = 00
        let len = b.len() as u16;
        z.extend_from_slice(&len.to_le_bytes());
        z.extend_from_slice(&(!len).to_le_bytes());
        z.extend_from_slice(b);
    }
    z.extend_from_slice(&adler32(&raw).to_be_bytes());
    let mut out = vec![0x89, b'P', b'N', b'G', 0x0D, 0x0A, 0x1A, 0x0A];
    let mut ihdr = Vec::with_capacity(13);
    ihdr.extend_from_slice(&(width as u32).to_be_bytes());
    ihdr.extend_from_slice(&(height as u32).to_be_bytes());
    ihdr.extend_from_slice(&[8, 3, 0, 0, 0]); // 8 bits, indexed, deflate, filter 0, no interlace
    chunk(&mut out, b"IHDR", &ihdr);
    let plte: Vec<u8> = palette.iter().flat_map(|&(r, g, b)| [r, g, b]).collect();
    chunk(&mut out, b"PLTE", &plte);
    chunk(&mut out, b"IDAT", &z);
    chunk(&mut out, b"IEND", &[]);
    Some(out)
}

/// Standard base64 (RFC 4648 §4) with padding.
pub(crate) fn base64(data: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::with_capacity(data.len().div_ceil(3) * 4);
    for c in data.chunks(3) {
        let n = (u32::from(c[0]) << 16)
            | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
            | u32::from(*c.get(2).unwrap_or(&0));
        for k in 0..4 {
            if k <= c.len() {
                s.push(char::from(A[((n >> (18 - 6 * k)) & 63) as usize]));
            } else {
                s.push('=');
            }
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checksums_match_their_reference_values() {
        // CRC-32 check value of "123456789" (ISO 3309 / PNG); Adler-32 of "Wikipedia" (RFC 1950
        // example value 0x11E60398)
        assert_eq!(crc32(0, b"123456789"), 0xCBF4_3926);
        assert_eq!(adler32(b"Wikipedia"), 0x11E6_0398);
        // the IEND chunk's CRC is the fixed 0xAE426082 of every PNG
        assert_eq!(crc32(0, b"IEND"), 0xAE42_6082);
    }

    #[test]
    fn base64_matches_rfc4648_vectors() {
        for (i, o) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(base64(i.as_bytes()), o);
        }
    }

    #[test]
    fn png_has_its_structure_and_refuses_bad_input() {
        let px: Vec<u8> = (0..200 * 400).map(|i| (i % 3) as u8).collect();
        let png = png_indexed(200, 400, &px, &[(0, 0, 0), (255, 0, 0), (0, 0, 255)]).unwrap();
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
        assert_eq!(&png[12..16], b"IHDR");
        assert_eq!(&png[png.len() - 8..png.len() - 4], b"IEND");
        // raw scanlines (200 + 1 filter byte) × 400 in two stored blocks, plus headers
        assert_eq!(png.len(), 8 + 25 + 21 + 12 + 2 + 2 * 5 + 201 * 400 + 4 + 12);
        assert!(png_indexed(0, 1, &[], &[(0, 0, 0)]).is_none());
        assert!(png_indexed(2, 1, &[0], &[(0, 0, 0)]).is_none());
        assert!(png_indexed(1, 1, &[1], &[(0, 0, 0)]).is_none());
    }
}
