//! How matrices appear in flexible-body files: as arrays of rows, so that a file reads like the
//! formulas (`c3[0]` is the first row of C3).

use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

fn rows(m: &DMatrix<f64>) -> Vec<Vec<f64>> {
    (0..m.nrows()).map(|r| m.row(r).iter().copied().collect()).collect()
}

fn from_rows<E: serde::de::Error>(rows: Vec<Vec<f64>>) -> Result<DMatrix<f64>, E> {
    let n = rows.first().map_or(0, Vec::len);
    if rows.iter().any(|r| r.len() != n) {
        return Err(E::custom("matrix rows have different lengths"));
    }
    Ok(DMatrix::from_fn(rows.len(), n, |r, c| rows[r][c]))
}

fn rows3(m: &Matrix3<f64>) -> [[f64; 3]; 3] {
    [0, 1, 2].map(|r| [0, 1, 2].map(|c| m[(r, c)]))
}

fn from_rows3(rows: [[f64; 3]; 3]) -> Matrix3<f64> {
    Matrix3::from_fn(|r, c| rows[r][c])
}

pub mod vector3 {
    use super::*;
    pub fn serialize<S: Serializer>(v: &Vector3<f64>, s: S) -> Result<S::Ok, S::Error> {
        [v.x, v.y, v.z].serialize(s)
    }
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vector3<f64>, D::Error> {
        let a = <[f64; 3]>::deserialize(d)?;
        Ok(Vector3::from(a))
    }
}

pub mod matrix3 {
    use super::*;
    pub fn serialize<S: Serializer>(m: &Matrix3<f64>, s: S) -> Result<S::Ok, S::Error> {
        rows3(m).serialize(s)
    }
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Matrix3<f64>, D::Error> {
        Ok(from_rows3(<[[f64; 3]; 3]>::deserialize(d)?))
    }
}

pub mod matrix3_list {
    use super::*;
    pub fn serialize<S: Serializer>(m: &[Matrix3<f64>], s: S) -> Result<S::Ok, S::Error> {
        m.iter().map(rows3).collect::<Vec<_>>().serialize(s)
    }
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<Matrix3<f64>>, D::Error> {
        Ok(Vec::<[[f64; 3]; 3]>::deserialize(d)?.into_iter().map(from_rows3).collect())
    }
}

pub mod matrix3_table {
    use super::*;
    pub fn serialize<S: Serializer>(m: &[Vec<Matrix3<f64>>], s: S) -> Result<S::Ok, S::Error> {
        m.iter().map(|row| row.iter().map(rows3).collect::<Vec<_>>()).collect::<Vec<_>>().serialize(s)
    }
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<Vec<Matrix3<f64>>>, D::Error> {
        Ok(Vec::<Vec<[[f64; 3]; 3]>>::deserialize(d)?
            .into_iter()
            .map(|row| row.into_iter().map(from_rows3).collect())
            .collect())
    }
}

pub mod dmatrix {
    use super::*;
    pub fn serialize<S: Serializer>(m: &DMatrix<f64>, s: S) -> Result<S::Ok, S::Error> {
        rows(m).serialize(s)
    }
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<DMatrix<f64>, D::Error> {
        from_rows(Vec::<Vec<f64>>::deserialize(d)?)
    }
}

pub mod dmatrix_list {
    use super::*;
    pub fn serialize<S: Serializer>(m: &[DMatrix<f64>], s: S) -> Result<S::Ok, S::Error> {
        m.iter().map(rows).collect::<Vec<_>>().serialize(s)
    }
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<DMatrix<f64>>, D::Error> {
        Vec::<Vec<Vec<f64>>>::deserialize(d)?.into_iter().map(from_rows).collect()
    }
}

pub mod dvector {
    use super::*;
    pub fn serialize<S: Serializer>(v: &DVector<f64>, s: S) -> Result<S::Ok, S::Error> {
        v.iter().copied().collect::<Vec<_>>().serialize(s)
    }
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<DVector<f64>, D::Error> {
        Ok(DVector::from_vec(Vec::<f64>::deserialize(d)?))
    }
}
