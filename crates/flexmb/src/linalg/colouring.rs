//! Greedy colouring of the column blocks of a sparse Jacobian (Curtis, Powell and Reid 1974): column
//! blocks that touch disjoint row blocks are perturbed together in one evaluation of a finite-difference
//! Jacobian, so its cost grows with the number of colours, not with the model's size.

/// Groups column blocks into colours, first fit in the order given: a block joins the first colour
/// none of whose blocks touches one of its row blocks, or opens a new colour. `touched[k]` lists the
/// row blocks (below `row_blocks`) that column block `k` touches. Returns the column blocks of each
/// colour, in the order given.
pub fn greedy_colouring(touched: &[Vec<usize>], row_blocks: usize) -> Vec<Vec<usize>> {
    let mut colours: Vec<Vec<usize>> = Vec::new();
    let mut used: Vec<Vec<bool>> = Vec::new();
    for (block, rows) in touched.iter().enumerate() {
        let slot = used.iter().position(|u| rows.iter().all(|&rb| !u[rb]));
        let c = slot.unwrap_or_else(|| {
            colours.push(Vec::new());
            used.push(vec![false; row_blocks]);
            colours.len() - 1
        });
        rows.iter().for_each(|&rb| used[c][rb] = true);
        colours[c].push(block);
    }
    colours
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Column blocks of a chain, each touching its own row block and its neighbours' (a tridiagonal
    /// block pattern), and a few long-range couplings.
    fn chain_with_links(n: usize) -> Vec<Vec<usize>> {
        let mut touched: Vec<Vec<usize>> = (0..n).map(|k| (k.saturating_sub(1)..(k + 2).min(n)).collect()).collect();
        for k in (0..n).step_by(7) {
            touched[k].push((k * 5 + 3) % n);
        }
        touched
    }

    /// Blocks of one colour touch disjoint rows, so one perturbation of all of them separates their
    /// columns exactly; every block has exactly one colour.
    #[test]
    fn blocks_of_one_colour_touch_disjoint_rows() {
        let touched = chain_with_links(40);
        let colours = greedy_colouring(&touched, 40);
        let mut coloured = vec![0; touched.len()];
        for colour in &colours {
            let mut rows = [false; 40];
            for &block in colour {
                coloured[block] += 1;
                for &r in &touched[block] {
                    assert!(!rows[r], "row block {r} is touched twice in one colour");
                    rows[r] = true;
                }
            }
        }
        assert!(coloured.iter().all(|&c| c == 1));
    }

    /// First fit: a block in colour `c` conflicts with some block of every earlier colour; a
    /// tridiagonal block pattern thus takes three colours, the fewest its 3-wide rows allow.
    #[test]
    fn every_block_takes_the_first_colour_it_fits() {
        let touched = chain_with_links(40);
        let colours = greedy_colouring(&touched, 40);
        let shares_a_row = |a: usize, b: usize| touched[a].iter().any(|r| touched[b].contains(r));
        for (c, colour) in colours.iter().enumerate() {
            for &block in colour {
                for earlier in &colours[..c] {
                    assert!(earlier.iter().any(|&other| other < block && shares_a_row(block, other)));
                }
            }
        }
        let tridiagonal: Vec<Vec<usize>> = (0..12).map(|k: usize| (k.saturating_sub(1)..(k + 2).min(12)).collect()).collect();
        assert_eq!(greedy_colouring(&tridiagonal, 12).len(), 3);
    }
}
