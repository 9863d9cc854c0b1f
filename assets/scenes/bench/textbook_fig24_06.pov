// textbook_fig24_06.pov -- POV-Ray 3.7 version of ../shared/bench/textbook_fig24_06.json
// (Suffern, "Ray Tracing from the Ground Up", Figure 24.6(b): Whitted mirrors, depth 10, 600x400,
// one point light), for timing POV-Ray against Penumbra side by side (scripts/bench_anchors.sh).
//
//   povray -D -GR +Itextbook_fig24_06.pov +O/tmp/fig.png +W600 +H400 +WT2 -A     (1 ray per pixel)
//   ... +A0.0 +AM1 +R4 +J     (a jittered 4x4 grid in every pixel: 16 rays, as Penumbra's --spp 16)
//
// The same scene as the JSON file, in the JSON file's right-handed coordinates (the camera's
// `right -x` makes POV-Ray right-handed), with Penumbra's classic Phong figures, so that the two
// images agree. What differs:
//  * the cylinder is the JSON's mesh (r 22, y 0..85, 256 segments, smooth side normals, flat caps:
//    the triangles of textbook_fig24_06_cylinder.obj), built here by a loop rather than read;
//  * POV-Ray has no 1/d^2 point light: fade_power 2 with fade_distance 1 gives 2 / (1 + d^2), so
//    the light's colour is half the JSON's intensity (the two differ by a factor 1 + 1/d^2, under
//    1e-4 anywhere in this scene);
//  * Penumbra's classic Phong is kd * E (kd the JSON's, already Suffern's kd * cd / pi) +
//    ks (r.v)^n E + ka * La + kr * L_mirror; POV-Ray's diffuse 1 on a pigment of kd, phong ks with
//    phong_size n (neither multiplied by n.l), reflection kr, and ambient ka * La / kd (the same
//    ratio in every channel of each material) on ambient_light 1 are the same sums;
//  * max_trace_level 11: POV-Ray counts the camera ray as a level, Penumbra's --max-depth 10
//    counts the mirror bounces after it;
//  * anti-aliasing: POV-Ray's +AM1 +R4 +J traces a jittered 4x4 grid per pixel and also the pixel
//    corners (about 6% more camera rays); Penumbra takes 16 multi-jittered samples, box filtered.
// With +A0.0 +AM1 +R4 +J the two images differ by 0.07 of 255 in mean absolute sRGB value.
#version 3.7;

global_settings { assumed_gamma 1.0 max_trace_level 11 ambient_light rgb 1 }

camera {
  perspective
  location <75, 40, 100>
  right -x * image_width / image_height
  up y
  angle 79.6111  // horizontal: 2 atan(1.5 tan(58.1092 / 2)), the JSON's vertical 58.1092 at 600x400
  look_at <-10, 39, 0>
}

background { rgb 0.15 }

light_source { <150, 150, 0> color rgb 51084.5 fade_distance 1 fade_power 2 }

// Phong(kd, ka_over_kd, ks, n, kr): the JSON's classic material.
#macro Phong(Kd, AmbientRatio, Ks, N, Kr)
  texture {
    pigment { rgb Kd }
    finish {
      ambient AmbientRatio diffuse 1
      #if (Ks > 0) phong Ks phong_size N #end
      #if (Kr > 0) reflection { Kr } #end
    }
  }
#end

sphere { <38, 23, -25>, 23 Phong(<0.119366, 0.119366, 0>, 0.785398, 0.15, 100, 0.75) }   // yellow mirror
sphere { <-7, 10, 42>, 20  Phong(<0.179049, 0.059683, 0>, 0.942478, 0, 1, 0) }          // orange
sphere { <-30, 59, 35>, 20 Phong(<0, 0, 0>, 0, 0, 1, 0.75) }                             // black mirror
box { <-35, 0, -110>, <-25, 60, 65> Phong(<0.119366, 0.159155, 0.119366>, 0.471239, 0, 1, 0) }  // light green
plane { y, 0 Phong(<0.286479, 0.286479, 0.286479>, 0.523599, 0, 1, 0) }                 // floor

// The cylinder: vertex k of the bottom ring is 22 (cos t, 0, sin t), t = 2 pi k / 256, with the
// smooth normal (cos t, 0, sin t); the top ring is the same at y = 85; the caps are fans from the
// ring's centre with flat normals.
#declare Segments = 256;
mesh2 {
  vertex_vectors {
    2 * Segments + 2,
    #for (K, 0, Segments - 1) <22 * cos(2 * pi * K / Segments), 0, 22 * sin(2 * pi * K / Segments)>, #end
    #for (K, 0, Segments - 1) <22 * cos(2 * pi * K / Segments), 85, 22 * sin(2 * pi * K / Segments)>, #end
    <0, 0, 0>, <0, 85, 0>
  }
  normal_vectors {
    Segments + 2,
    #for (K, 0, Segments - 1) <cos(2 * pi * K / Segments), 0, sin(2 * pi * K / Segments)>, #end
    <0, -1, 0>, <0, 1, 0>
  }
  face_indices {
    4 * Segments,
    #for (K, 0, Segments - 1)
      #local Next = mod(K + 1, Segments);
      <K, Segments + K, Next>, <Next, Segments + K, Segments + Next>,
      <2 * Segments, Next, K>, <2 * Segments + 1, Segments + K, Segments + Next>,
    #end
  }
  normal_indices {
    4 * Segments,
    #for (K, 0, Segments - 1)
      #local Next = mod(K + 1, Segments);
      <K, K, Next>, <Next, K, Next>, <Segments, Segments, Segments>, <Segments + 1, Segments + 1, Segments + 1>,
    #end
  }
  Phong(<0, 0.079577, 0.119366>, 1.099557, 0.2, 100, 0.75)  // cyan mirror
}
