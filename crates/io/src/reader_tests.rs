//! Unit tests of the Cornell and CSV readers through their entry points.

/// The cornell reader's tests (apart, since the readers' entry points are in `format`).
mod cornell {
    use crate::DataError;
    use crate::format::parse_cornell;
    use brdf_model::Filters;
    use std::path::Path;

    #[test]
    fn cornell_errors() {
        let path = Path::new("x.brdf");
        let f = Filters::default();
        let e = parse_cornell("# only comments\n", path, 550.0, &f).unwrap_err();
        assert!(matches!(e, DataError::Parse { line: 0, .. }), "{e}");
        let e = parse_cornell("two\n", path, 550.0, &f).unwrap_err();
        assert!(matches!(e, DataError::Parse { line: 1, .. }), "{e}");
        let e = parse_cornell("2\n500 550\n0 0 0 0 1\n", path, 550.0, &f).unwrap_err();
        assert!(
            e.to_string().contains("x.brdf:3: expected 6 numbers"),
            "{e}"
        );
        let e = parse_cornell("2\n500 550\n0 0 0 0 1 q\n", path, 550.0, &f).unwrap_err();
        assert!(matches!(e, DataError::Parse { line: 3, .. }), "{e}");
        let e = parse_cornell("2\n500 600\n", path, 550.0, &f).unwrap_err();
        assert!(matches!(e, DataError::NoWavelength { .. }), "{e}");
        let e = parse_cornell("2\n500\n", path, 550.0, &f).unwrap_err();
        assert!(e.to_string().contains("end of file after 1"), "{e}");
        let (d, rep) = parse_cornell("2\n500\n550\n0.1 0 0.1 3.14 1 2\n", path, 550.0, &f).unwrap();
        assert_eq!((d.len(), rep.read), (1, 1));
        assert_eq!(d.value(0), 2.0);
    }
}

/// The csv reader's tests (apart, since the readers' entry points are in `format`).
mod csv {
    use crate::DataError;
    use crate::format::parse_csv;
    use brdf_model::Filters;
    use std::path::Path;

    fn p() -> &'static Path {
        Path::new("t.csv")
    }

    #[test]
    fn csv_vectors_and_angles() {
        let text = "# comment\nux, uy, uz, vx, vy, vz, value\n0,0,2,0,0,1,0.5\n0,0,1,0,0,-1,0.2\n";
        let (d, rep) = parse_csv(text, p(), &Filters::default()).unwrap();
        assert_eq!(d.len(), 1);
        assert_eq!(d.u(0), [0.0, 0.0, 1.0]);
        assert_eq!(rep.below_horizon, 1);
        let text = "theta_i,phi_i,theta_o,phi_o,value,extra\n90,0,0,0,0.25,1\n";
        let (d, _) = parse_csv(text, p(), &Filters::default()).unwrap();
        assert!((d.u(0)[0] - 1.0).abs() < 1e-15 && d.u(0)[2].abs() < 1e-15);
        assert_eq!(d.value(0), 0.25);
    }

    #[test]
    fn csv_errors_name_line_and_expectation() {
        let e = parse_csv("a,b\n1,2\n", p(), &Filters::default()).unwrap_err();
        assert!(matches!(e, DataError::Parse { line: 1, .. }), "{e}");
        let e = parse_csv(
            "ux,uy,uz,vx,vy,vz,value\n0,0,1,0,0,1,x\n",
            p(),
            &Filters::default(),
        )
        .unwrap_err();
        let msg = e.to_string();
        assert!(
            msg.contains("t.csv:2") && msg.contains("column `value`"),
            "{msg}"
        );
        let e = parse_csv(
            "ux,uy,uz,vx,vy,vz,value\n0,0,1,0,0,1\n",
            p(),
            &Filters::default(),
        )
        .unwrap_err();
        assert!(e.to_string().contains("7 comma-separated fields"), "{e}");
        let e = parse_csv(
            "ux,uy,uz,vx,vy,vz,value\n0,0,0,0,0,1,1\n",
            p(),
            &Filters::default(),
        )
        .unwrap_err();
        assert!(e.to_string().contains("non-zero direction u"), "{e}");
        assert!(matches!(
            parse_csv("", p(), &Filters::default()),
            Err(DataError::Parse { line: 0, .. })
        ));
    }

    #[test]
    fn csv_round_trip() {
        let params = brdf_model::named_params("cross").unwrap();
        let d = brdf_model::synthetic(&params, 50, 0.1, 9);
        let mut buf = Vec::new();
        d.write_csv(&mut buf).unwrap();
        let (back, _) =
            parse_csv(std::str::from_utf8(&buf).unwrap(), p(), &Filters::none()).unwrap();
        assert_eq!(back.len(), 50);
        for i in 0..50 {
            assert_eq!(back.value(i), d.value(i));
            for k in 0..3 {
                assert!((back.u(i)[k] - d.u(i)[k]).abs() < 1e-15);
            }
        }
    }
}
