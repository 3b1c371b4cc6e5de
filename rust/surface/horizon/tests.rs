use super::*;

#[test]
fn round_up_is_the_least_f32_at_or_above() {
    // Against the branchy definition, on special values, f32 neighbours and their midpoints,
    // and a spread of magnitudes and signs from a fixed xorshift stream.
    let reference = |x: f64| {
        let f = x as f32;
        if f64::from(f) < x {
            f.next_up()
        } else {
            f
        }
    };
    let mut values = vec![0.0, -0.0, f64::INFINITY, f64::NEG_INFINITY, f64::MIN_POSITIVE, -f64::MIN_POSITIVE, 1e-300, -1e-300];
    for f in [f32::MAX, f32::MIN, f32::MIN_POSITIVE, -f32::MIN_POSITIVE, 1.0, -1.0, 1e-45, -1e-45, 3.5, -3.5] {
        let x = f64::from(f);
        let next = f64::from(f.next_up());
        values.extend([x, x.next_up(), x.next_down(), 0.5 * (x + next), x * (1.0 + 1e-12), x * (1.0 - 1e-12)]);
    }
    values.extend([f64::from(f32::MAX) * 1.5, f64::from(f32::MIN) * 1.5, f64::MAX, f64::MIN]);
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    for _ in 0..200_000 {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        let exponent = (state >> 52) % 120;
        let magnitude = (state >> 11) as f64 / (1u64 << 53) as f64 * 2f64.powi(exponent as i32 - 60);
        values.push(if state & 1 == 0 { magnitude } else { -magnitude });
    }
    for x in values {
        let (got, want) = (round_up(x), reference(x));
        assert_eq!(got.to_bits(), want.to_bits(), "{x:e}: {got:e} against {want:e}");
        assert!(f64::from(got) >= x || x.is_nan() || got.is_nan(), "{x:e}");
    }
    assert!(round_up(f64::NAN).is_nan());
}

#[test]
fn a_box_raises_its_sectors_and_their_spares_only() {
    // Boxes anywhere around the UAV but across the +x axis (where the sectors wrap) raise,
    // in one distance bin, the sectors from their corners' least to their greatest, with
    // one spare on each side, all to one bound, and nothing else: narrow ones through the
    // fixed window, wide ones (near the UAV) through the loop.
    let bounds = ([-30.0, -30.0, 0.0], [30.0, 30.0, 5.0]);
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut narrow = 0;
    for _ in 0..2000 {
        let (size, angle, dist) = (0.25 + 1.75 * next(), 6.2 * next(), 0.8 + 18.0 * next());
        let (xlo, ylo) = (dist * angle.cos(), dist * angle.sin());
        let (xhi, yhi) = (xlo + size, ylo + size);
        if ylo <= 0.0 && yhi >= 0.0 && xhi > 0.0 || xlo <= 0.0 && xhi >= 0.0 && ylo <= 0.0 && yhi >= 0.0 {
            continue; // across the +x axis, or over the UAV
        }
        let mut h = HorizonBuilder::new([0.0, 0.0, 10.0], 20.0, usize::MAX, 0.5, bounds, 30.0, 5.0).unwrap();
        let corners = [(xlo, ylo), (xhi, ylo), (xlo, yhi), (xhi, yhi)].map(|(x, y)| h.corner_sector(x, y));
        let (least, most) = (*corners.iter().min().unwrap(), *corners.iter().max().unwrap());
        if least == 0 || most + 1 >= h.sectors || xlo.hypot(ylo).min(xhi.hypot(yhi)) >= 19.0 {
            continue;
        }
        h.put_box(2.0 + 10.0 * next(), (xlo, xhi), (ylo, yhi), corners);
        let raised: Vec<usize> = (0..h.by_bin.len()).filter(|&k| h.by_bin[k] > f32::NEG_INFINITY).collect();
        let bin = raised[0] / h.sectors;
        let sectors: Vec<usize> = raised.iter().map(|&k| k - bin * h.sectors).collect();
        assert_eq!(sectors, (least - 1..=most + 1).collect::<Vec<_>>(), "box at {xlo} {ylo}, size {size}");
        assert!(raised.iter().all(|&k| h.by_bin[k] == h.by_bin[raised[0]]));
        narrow += usize::from(most + 2 - least < WINDOW);
    }
    assert!(narrow > 500, "{narrow} boxes through the window");
}
