//! The renderer: camera fit, coverage, depth order, two-sided Lambert shading, colour map, PNG output
//! and errors. Expected pixels follow from the documented camera rule and Lambert's law, computed here.

use cosserat_io::render::{
    Colouring, Image, Projection, RenderError, RenderOptions, ScalarMode, render_image, render_png,
    render_side_by_side, viridis,
};
use cosserat_io::{DataArray, RunWriter, VtuFrame, read_pvd_frame};

use super::test_dir;

/// The unit square `[0, 1]^2` at height `z`, as two triangles.
fn square(z: f64) -> VtuFrame {
    VtuFrame::new(
        vec![[0.0, 0.0, z], [1.0, 0.0, z], [1.0, 1.0, z], [0.0, 1.0, z]],
        vec![[0, 1, 2], [0, 2, 3]],
        0.0,
    )
}

/// Orthographic view straight down the z axis (from +z, y up), one sample per pixel, 800 x 600.
fn top_view() -> RenderOptions {
    RenderOptions {
        view_direction: [0.0, 0.0, 1.0],
        up: [0.0, 1.0, 0.0],
        projection: Projection::Orthographic,
        supersampling: 1,
        ..RenderOptions::default()
    }
}

/// Lambert intensity of a surface facing the viewer under the default light (given in view coordinates).
fn facing_intensity(options: &RenderOptions) -> f64 {
    let [x, y, z] = options.light_direction;
    let cos = z / (x * x + y * y + z * z).sqrt();
    options.ambient + (1.0 - options.ambient) * cos
}

fn assert_close(pixel: [u8; 3], expected: [f64; 3], tolerance: f64, what: &str) {
    for c in 0..3 {
        assert!(
            (f64::from(pixel[c]) - expected[c]).abs() <= tolerance,
            "{what}: {pixel:?} vs {expected:?}"
        );
    }
}

#[test]
fn unit_square_facing_the_camera_covers_the_fitted_rectangle() {
    let options = top_view();
    let image = render_image(&square(0.0), &options).expect("render");
    assert_eq!((image.width, image.height), (800, 600));
    let background = options.background;
    assert_ne!(image.pixel(400, 300), background, "centre");
    for (x, y) in [(0, 0), (799, 0), (0, 599), (799, 599)] {
        assert_eq!(image.pixel(x, y), background, "corner ({x}, {y})");
    }
    // Documented fit: the 1 x 1 square is scaled by min(0.9 * 800, 0.9 * 600) = 540 pixels per unit and
    // centred, so it covers x in [130, 670] and y in [30, 570]; pixel (i, j) samples (i + 0.5, j + 0.5).
    for (x, y) in [(131, 300), (668, 300), (400, 31), (400, 568)] {
        assert_ne!(image.pixel(x, y), background, "inside at ({x}, {y})");
    }
    for (x, y) in [(128, 300), (671, 300), (400, 28), (400, 571)] {
        assert_eq!(image.pixel(x, y), background, "outside at ({x}, {y})");
    }
}

#[test]
fn flat_surface_has_the_lambert_intensity_of_the_light() {
    let options = top_view();
    let image = render_image(&square(0.0), &options).expect("render");
    let intensity = facing_intensity(&options);
    let expected = options.surface_colour.map(|c| f64::from(c) * intensity);
    for (x, y) in [(400, 300), (200, 100), (600, 500)] {
        assert_close(image.pixel(x, y), expected, 0.5, "uniform shading");
    }
}

#[test]
fn both_sides_of_a_shell_are_lit_alike() {
    let front = render_image(&square(0.0), &top_view()).expect("front");
    let from_below = RenderOptions {
        view_direction: [0.0, 0.0, -1.0],
        ..top_view()
    };
    let back = render_image(&square(0.0), &from_below).expect("back");
    assert_eq!(front.pixel(400, 300), back.pixel(400, 300));
    assert_ne!(back.pixel(400, 300), from_below.background);
}

#[test]
fn nearer_surfaces_hide_farther_ones_whatever_the_order() {
    // A large square at z = 0 with scalar 0 and a small one at z = 0.5 with scalar 1 above its centre.
    let mut frame = VtuFrame::new(
        vec![
            [-1.0, -1.0, 0.0],
            [2.0, -1.0, 0.0],
            [2.0, 2.0, 0.0],
            [-1.0, 2.0, 0.0],
            [0.25, 0.25, 0.5],
            [0.75, 0.25, 0.5],
            [0.75, 0.75, 0.5],
            [0.25, 0.75, 0.5],
        ],
        vec![[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]],
        0.0,
    );
    frame.point_data.push(DataArray::scalars(
        "level",
        vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0],
    ));
    let colouring = Colouring::PointScalar {
        array: "level".to_owned(),
        mode: ScalarMode::Component(0),
        range: Some([0.0, 1.0]),
    };
    let options = RenderOptions {
        colouring,
        ..top_view()
    };
    let intensity = facing_intensity(&options);
    let shaded = |t: f64| viridis(t).map(|c| f64::from(c) * intensity);
    // Centre of the image is the centre of the bounding box, (0.5, 0.5), covered by both squares.
    let image = render_image(&frame, &options).expect("render");
    assert_close(image.pixel(400, 300), shaded(1.0), 1.0, "near square from above");

    let mut reversed = frame.clone();
    reversed.triangles.reverse();
    assert_eq!(
        render_image(&reversed, &options).expect("render"),
        image,
        "draw order must not matter"
    );

    let from_below = RenderOptions {
        view_direction: [0.0, 0.0, -1.0],
        ..options
    };
    let below = render_image(&frame, &from_below).expect("render");
    assert_close(below.pixel(400, 300), shaded(0.0), 1.0, "large square from below");
}

#[test]
fn scalar_colour_follows_the_map_across_the_surface() {
    // Scalar equal to x on the unit square: pixel column i samples x = (i + 0.5 - 130) / 540.
    let mut frame = square(0.0);
    frame.point_data.push(DataArray::vectors(
        "u",
        &[[0.0, 0.0, 0.0], [3.0, 4.0, 0.0], [3.0, 4.0, 0.0], [0.0, 0.0, 0.0]],
    ));
    let colouring = Colouring::PointScalar {
        array: "u".to_owned(),
        mode: ScalarMode::Magnitude,
        range: None,
    };
    let options = RenderOptions {
        colouring,
        ..top_view()
    };
    let image = render_image(&frame, &options).expect("render");
    let intensity = facing_intensity(&options);
    for i in [140u32, 250, 400, 520, 660] {
        let t = (f64::from(i) + 0.5 - 130.0) / 540.0;
        // The auto range is [0, 5], the magnitudes at x = 0 and x = 1; the map is linear in between.
        let expected = viridis(t).map(|c| f64::from(c) * intensity);
        assert_close(image.pixel(i, 300), expected, 1.5, &format!("column {i}"));
    }
}

#[test]
fn perspective_default_view_frames_the_mesh() {
    let mut frame = square(0.0);
    frame.points[2][2] = 0.3;
    let options = RenderOptions {
        width: 200,
        height: 150,
        ..RenderOptions::default()
    };
    let image = render_image(&frame, &options).expect("render");
    assert_ne!(image.pixel(100, 75), options.background, "centre");
    for (x, y) in [(0, 0), (199, 0), (0, 149), (199, 149)] {
        assert_eq!(image.pixel(x, y), options.background, "corner ({x}, {y})");
    }
    let rows_with_surface = (0..150)
        .filter(|&y| (0..200).any(|x| image.pixel(x, y) != options.background))
        .count();
    let cols_with_surface = (0..200)
        .filter(|&x| (0..150).any(|y| image.pixel(x, y) != options.background))
        .count();
    // The fit fills the image minus the 5 % margins along at least one axis.
    assert!(
        rows_with_surface >= 133 || cols_with_surface >= 178,
        "{rows_with_surface} rows, {cols_with_surface} columns"
    );
}

#[test]
fn side_by_side_panels_share_one_camera() {
    let left = square(0.0);
    let mut right = square(0.0);
    right.time = 1.0;
    for p in &mut right.points {
        p[0] += 2.0;
    }
    let options = RenderOptions {
        width: 300,
        height: 200,
        ..top_view()
    };
    let image = render_side_by_side(&[left, right], &options).expect("render");
    assert_eq!((image.width, image.height), (600, 200));
    // The union spans x in [0, 3]: scale min(0.9 * 300 / 3, 0.9 * 200 / 1) = 90, so the left square covers
    // panel columns [15, 105] and the right one [195, 285].
    let bg = options.background;
    assert_ne!(image.pixel(60, 100), bg);
    assert_eq!(image.pixel(240, 100), bg);
    assert_eq!(image.pixel(300 + 60, 100), bg);
    assert_ne!(image.pixel(300 + 240, 100), bg);
}

#[test]
fn png_decodes_to_the_requested_size_and_pixels() {
    let dir = test_dir("render_png");
    let path = dir.join("square.png");
    let options = RenderOptions {
        width: 64,
        height: 40,
        ..top_view()
    };
    render_png(&square(0.0), &options, &path).expect("render");
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&path).expect("open")));
    let mut reader = decoder.read_info().expect("PNG header");
    let mut buffer = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buffer).expect("PNG data");
    assert_eq!((info.width, info.height), (64, 40));
    assert_eq!(
        (info.color_type, info.bit_depth),
        (png::ColorType::Rgb, png::BitDepth::Eight)
    );
    let expected: Image = render_image(&square(0.0), &options).expect("render");
    assert_eq!(&buffer[..info.buffer_size()], expected.pixels.as_flattened());
}

#[test]
fn a_frame_chosen_from_a_run_renders() {
    let dir = test_dir("render_run_frame");
    let mut writer = RunWriter::create(&dir, &[] as &[&str]).expect("create");
    writer.write_frame(&square(0.0)).expect("frame 0");
    let mut lifted = square(0.0);
    lifted.time = 1.0;
    lifted.points[2][2] = 0.5;
    writer.write_frame(&lifted).expect("frame 1");
    let frame = read_pvd_frame(&writer.pvd_path(), 1).expect("frame 1");
    let options = RenderOptions {
        width: 80,
        height: 60,
        ..RenderOptions::default()
    };
    assert_eq!(
        render_image(&frame, &options).expect("render"),
        render_image(&lifted, &options).expect("render")
    );
}

#[test]
fn unrenderable_input_gives_clear_errors() {
    let options = RenderOptions {
        width: 40,
        height: 30,
        ..top_view()
    };

    let empty = VtuFrame::new(Vec::new(), Vec::new(), 0.0);
    let error = render_image(&empty, &options).expect_err("empty mesh");
    assert!(
        matches!(
            error,
            RenderError::EmptyMesh {
                frame_idx: 0,
                n_points: 0,
                n_triangles: 0
            }
        ),
        "{error:?}"
    );
    assert!(error.to_string().contains("empty"));
    let points_only = VtuFrame::new(square(0.0).points, Vec::new(), 0.0);
    assert!(matches!(
        render_image(&points_only, &options),
        Err(RenderError::EmptyMesh { n_triangles: 0, .. })
    ));
    assert!(matches!(render_side_by_side(&[], &options), Err(RenderError::NoFrames)));

    let mut nan = square(0.0);
    nan.points[1][1] = f64::NAN;
    assert!(matches!(
        render_image(&nan, &options),
        Err(RenderError::Frame { frame_idx: 0, .. })
    ));

    let point = VtuFrame::new(vec![[1.0, 1.0, 1.0]; 3], vec![[0, 1, 2]], 0.0);
    assert!(matches!(
        render_image(&point, &options),
        Err(RenderError::DegenerateView { .. })
    ));

    let missing = RenderOptions {
        colouring: Colouring::PointScalar {
            array: "u".to_owned(),
            mode: ScalarMode::Magnitude,
            range: None,
        },
        ..options.clone()
    };
    assert!(matches!(
        render_image(&square(0.0), &missing),
        Err(RenderError::MissingArray { .. })
    ));
    let mut with_scalar = square(0.0);
    with_scalar.point_data.push(DataArray::scalars("u", vec![0.0; 4]));
    let component = RenderOptions {
        colouring: Colouring::PointScalar {
            array: "u".to_owned(),
            mode: ScalarMode::Component(1),
            range: None,
        },
        ..options.clone()
    };
    assert!(matches!(
        render_image(&with_scalar, &component),
        Err(RenderError::ComponentOutOfRange {
            component: 1,
            n_components: 1,
            ..
        })
    ));

    let invalid = [
        RenderOptions {
            supersampling: 0,
            ..options.clone()
        },
        RenderOptions {
            margin: 0.5,
            ..options.clone()
        },
        RenderOptions {
            ambient: -0.1,
            ..options.clone()
        },
        RenderOptions {
            view_direction: [0.0; 3],
            ..options.clone()
        },
        RenderOptions {
            light_direction: [f64::NAN, 0.0, 1.0],
            ..options.clone()
        },
        RenderOptions {
            projection: Projection::Perspective { fov_y_degrees: 180.0 },
            ..options.clone()
        },
    ];
    for bad in invalid {
        assert!(
            matches!(render_image(&square(0.0), &bad), Err(RenderError::InvalidOption { .. })),
            "{bad:?}"
        );
    }
    let zero = RenderOptions {
        width: 0,
        ..options.clone()
    };
    assert!(matches!(
        render_image(&square(0.0), &zero),
        Err(RenderError::ImageSize { .. })
    ));
    let huge = RenderOptions {
        width: 100_000,
        height: 100_000,
        ..options
    };
    assert!(matches!(
        render_image(&square(0.0), &huge),
        Err(RenderError::ImageSize { .. })
    ));
}
