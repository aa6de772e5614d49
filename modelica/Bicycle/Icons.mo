within Bicycle;
package Icons "Icons of the library's packages and classes (as Modelica.Icons)"
  partial package Package "Icon of a package (as Modelica.Icons.Package)"
    annotation(
      Icon(graphics = {
        Rectangle(extent = {{-100, -100}, {100, 100}}, lineColor = {200, 200, 200}, fillColor = {248, 248, 248}, fillPattern = FillPattern.HorizontalCylinder, radius = 25),
        Rectangle(extent = {{-100, -100}, {100, 100}}, lineColor = {128, 128, 128}, radius = 25)}),
      Documentation(info = "<html>
<p>Standard icon of the library's packages.</p>
</html>"));
  end Package;

  partial package ExamplesPackage "Icon of a package of examples (as Modelica.Icons.ExamplesPackage)"
    extends Bicycle.Icons.Package;
    annotation(
      Icon(graphics = {
        Polygon(origin = {8, 14}, points = {{-58, 46}, {42, -14}, {-58, -74}, {-58, 46}}, lineColor = {78, 138, 73}, fillColor = {78, 138, 73}, fillPattern = FillPattern.Solid, pattern = LinePattern.None)}));
  end ExamplesPackage;

  partial package InterfacesPackage "Icon of a package of connectors (as Modelica.Icons.InterfacesPackage)"
    extends Bicycle.Icons.Package;
    annotation(
      Icon(graphics = {
        Polygon(origin = {20, 0}, points = {{-10, 70}, {10, 70}, {40, 20}, {80, 20}, {80, -20}, {40, -20}, {10, -70}, {-10, -70}}, lineColor = {64, 64, 64}, fillColor = {255, 255, 255}, fillPattern = FillPattern.Solid),
        Polygon(points = {{-100, 20}, {-60, 20}, {-30, 70}, {-10, 70}, {-10, -70}, {-30, -70}, {-60, -20}, {-100, -20}}, lineColor = {102, 102, 102}, fillColor = {102, 102, 102}, fillPattern = FillPattern.Solid, pattern = LinePattern.None)}));
  end InterfacesPackage;

  partial package SourcesPackage "Icon of a package of sources (as Modelica.Icons.SourcesPackage)"
    extends Bicycle.Icons.Package;
    annotation(
      Icon(graphics = {
        Polygon(origin = {23.33, 0}, points = {{-23.33, 30}, {46.67, 0}, {-23.33, -30}}, lineColor = {128, 128, 128}, fillColor = {128, 128, 128}, fillPattern = FillPattern.Solid, pattern = LinePattern.None),
        Rectangle(extent = {{-70, -4.5}, {0, 4.5}}, lineColor = {128, 128, 128}, fillColor = {128, 128, 128}, fillPattern = FillPattern.Solid, pattern = LinePattern.None)}));
  end SourcesPackage;

  partial class Information "Icon of a page of the User's Guide (as Modelica.Icons.Information)"
    annotation(
      Icon(graphics = {
        Ellipse(extent = {{-100, -100}, {100, 100}}, lineColor = {75, 138, 73}, fillColor = {75, 138, 73}, fillPattern = FillPattern.Solid),
        Rectangle(extent = {{-12, -60}, {12, 20}}, lineColor = {255, 255, 255}, fillColor = {255, 255, 255}, fillPattern = FillPattern.Solid, pattern = LinePattern.None, radius = 4),
        Ellipse(extent = {{-15, 35}, {15, 65}}, lineColor = {255, 255, 255}, fillColor = {255, 255, 255}, fillPattern = FillPattern.Solid, pattern = LinePattern.None)}));
  end Information;

  partial model Example "Icon of a runnable example (as Modelica.Icons.Example)"
    annotation(
      Icon(graphics = {
        Ellipse(extent = {{-100, -100}, {100, 100}}, lineColor = {75, 138, 73}, fillColor = {255, 255, 255}, fillPattern = FillPattern.Solid),
        Polygon(points = {{-36, 60}, {64, 0}, {-36, -60}, {-36, 60}}, lineColor = {0, 0, 255}, fillColor = {75, 138, 73}, fillPattern = FillPattern.Solid, pattern = LinePattern.None),
        Text(extent = {{-150, 110}, {150, 150}}, textString = "%name", textColor = {0, 0, 255})}));
  end Example;

  partial block Block "Icon of a block: controllers, sources, the rider's delay (as Modelica.Blocks.Icons.Block)"
    annotation(
      Icon(graphics = {
        Rectangle(extent = {{-100, -100}, {100, 100}}, lineColor = {0, 0, 127}, fillColor = {255, 255, 255}, fillPattern = FillPattern.Solid),
        Text(extent = {{-150, 110}, {150, 150}}, textString = "%name", textColor = {0, 0, 255})}));
  end Block;

  partial model Bike "Icon of a bicycle: side view with rear wheel, frame, fork, handlebar and front wheel"
    annotation(
      Icon(graphics = {
        Ellipse(extent = {{-92, -74}, {-20, -2}}, lineColor = {0, 0, 0}, lineThickness = 0.75),
        Ellipse(extent = {{-86, -68}, {-26, -8}}, lineColor = {160, 160, 160}),
        Ellipse(extent = {{-60, -42}, {-52, -34}}, lineColor = {0, 0, 0}, fillColor = {0, 0, 0}, fillPattern = FillPattern.Solid),
        Ellipse(extent = {{20, -74}, {92, -2}}, lineColor = {0, 0, 0}, lineThickness = 0.75),
        Ellipse(extent = {{26, -68}, {86, -8}}, lineColor = {160, 160, 160}),
        Ellipse(extent = {{52, -42}, {60, -34}}, lineColor = {0, 0, 0}, fillColor = {0, 0, 0}, fillPattern = FillPattern.Solid),
        Line(points = {{-56, -38}, {-12, -44}, {-24, 18}, {-56, -38}}, color = {64, 64, 64}, thickness = 0.75),
        Line(points = {{-24, 18}, {32, 18}, {38, 2}, {-12, -44}}, color = {64, 64, 64}, thickness = 0.75),
        Line(points = {{-24, 18}, {-27, 28}}, color = {64, 64, 64}, thickness = 0.75),
        Line(points = {{-38, 29}, {-16, 29}}, color = {0, 0, 0}, thickness = 1.5),
        Line(points = {{38, 2}, {52, -30}, {56, -38}}, color = {64, 64, 64}, thickness = 0.75, smooth = Smooth.Bezier),
        Line(points = {{32, 18}, {30, 26}, {19, 29}, {16, 24}}, color = {64, 64, 64}, thickness = 0.75),
        Ellipse(extent = {{-18, -50}, {-6, -38}}, lineColor = {64, 64, 64}),
        Line(points = {{-100, -74}, {100, -74}}, color = {0, 0, 0}),
        Text(extent = {{-150, 110}, {150, 150}}, textString = "%name", textColor = {0, 0, 255})}));
  end Bike;

  partial model BikeRider "Icon of a bicycle with a rider whose upper body leans on a hip hinge"
    extends Bicycle.Icons.Bike;
    annotation(
      Icon(graphics = {
        Line(points = {{-24, 34}, {4, 4}, {-8, -40}}, color = {0, 0, 160}, thickness = 1),
        Line(points = {{-24, 34}, {-4, 62}}, color = {0, 0, 160}, thickness = 2.5),
        Line(points = {{-4, 62}, {10, 44}, {19, 30}}, color = {0, 0, 160}, thickness = 1),
        Ellipse(extent = {{-5, 69}, {13, 87}}, lineColor = {0, 0, 160}, fillColor = {0, 0, 160}, fillPattern = FillPattern.Solid),
        Ellipse(extent = {{-29, 29}, {-19, 39}}, lineColor = {0, 0, 0}, fillColor = {255, 255, 255}, fillPattern = FillPattern.Solid)}));
  end BikeRider;

  partial model Wheel "Icon of a wheel: tyre, rim, spokes and the hub (its frame up to the top border)"
    annotation(
      Icon(graphics = {
        Ellipse(extent = {{-100, -100}, {100, 100}}, lineColor = {0, 0, 0}, fillColor = {64, 64, 64}, fillPattern = FillPattern.Solid),
        Ellipse(extent = {{-84, -84}, {84, 84}}, lineColor = {95, 95, 95}, fillColor = {245, 245, 245}, fillPattern = FillPattern.Solid),
        Line(points = {{-84, 0}, {84, 0}}, color = {160, 160, 160}),
        Line(points = {{0, -84}, {0, 84}}, color = {160, 160, 160}),
        Line(points = {{-59, -59}, {59, 59}}, color = {160, 160, 160}),
        Line(points = {{-59, 59}, {59, -59}}, color = {160, 160, 160}),
        Ellipse(extent = {{-16, -16}, {16, 16}}, lineColor = {0, 0, 0}, fillColor = {192, 192, 192}, fillPattern = FillPattern.Solid),
        Text(extent = {{20, 104}, {170, 144}}, textString = "%name", textColor = {0, 0, 255}, horizontalAlignment = TextAlignment.Left)}));
  end Wheel;

  partial model RearFrameIcon "Icon of a rear frame: the frame triangles with the saddle, rear axle on the left, steer head on the right"
    annotation(
      Icon(graphics = {
        Line(points = {{-76, 0}, {2, -30}, {-30, 56}, {-76, 0}}, color = {64, 64, 64}, thickness = 1),
        Line(points = {{-30, 56}, {70, 50}, {76, 18}, {2, -30}}, color = {64, 64, 64}, thickness = 1),
        Line(points = {{70, 50}, {76, 18}}, color = {64, 64, 64}, thickness = 2),
        Line(points = {{-30, 56}, {-34, 70}}, color = {64, 64, 64}, thickness = 1),
        Line(points = {{-52, 72}, {-18, 72}}, color = {0, 0, 0}, thickness = 2),
        Ellipse(extent = {{-84, -8}, {-68, 8}}, lineColor = {0, 0, 0}, fillColor = {192, 192, 192}, fillPattern = FillPattern.Solid),
        Ellipse(extent = {{-8, -38}, {12, -18}}, lineColor = {64, 64, 64}),
        Text(extent = {{-150, 110}, {150, 150}}, textString = "%name", textColor = {0, 0, 255})}));
  end RearFrameIcon;

  partial model FrontFrameIcon "Icon of a front frame: handlebar, steer tube and fork on the tilted steer axis, front axle at the bottom"
    annotation(
      Icon(graphics = {
        Line(points = {{-60, 112}, {16, -100}}, color = {128, 128, 128}, pattern = LinePattern.DashDot),
        Line(points = {{-14, 14}, {-2, -24}, {10, -76}}, color = {160, 160, 160}, thickness = 2, smooth = Smooth.Bezier),
        Line(points = {{-26, 16}, {-10, -30}, {0, -80}}, color = {64, 64, 64}, thickness = 2, smooth = Smooth.Bezier),
        Line(points = {{-44, 66}, {-26, 16}}, color = {64, 64, 64}, thickness = 4),
        Line(points = {{-44, 66}, {-48, 80}, {-70, 86}, {-90, 78}, {-88, 56}, {-74, 50}}, color = {64, 64, 64}, thickness = 2, smooth = Smooth.Bezier),
        Ellipse(extent = {{-10, -90}, {10, -70}}, lineColor = {0, 0, 0}, fillColor = {192, 192, 192}, fillPattern = FillPattern.Solid),
        Text(extent = {{-150, 110}, {150, 150}}, textString = "%name", textColor = {0, 0, 255})}));
  end FrontFrameIcon;

  partial model SteerAxisIcon "Icon of the steer axis: the head tube on its axis, tilted back by lam"
    annotation(
      Icon(graphics = {
        Line(points = {{-100, 0}, {-26, 0}}, color = {95, 95, 95}, thickness = 0.5),
        Line(points = {{26, 0}, {100, 0}}, color = {95, 95, 95}, thickness = 0.5),
        Rectangle(rotation = 20, extent = {{-18, -62}, {18, 62}}, lineColor = {64, 64, 64}, fillColor = {192, 192, 192}, fillPattern = FillPattern.VerticalCylinder, radius = 6),
        Line(rotation = 20, points = {{0, -96}, {0, 96}}, color = {0, 0, 0}, thickness = 0.5, pattern = LinePattern.DashDot),
        Line(origin = {-18, 46}, rotation = 20, points = {{-41.3, -15}, {-35.5, -26}, {-26.8, -34.9}, {-15.9, -41}, {-3.8, -43.8}, {8.6, -43.2}, {20.3, -39}, {30.4, -31.8}, {38.1, -22}}, color = {0, 0, 0}, arrow = {Arrow.None, Arrow.Filled}, arrowSize = 6, smooth = Smooth.Bezier),
        Text(extent = {{40, 90}, {100, 50}}, textString = "λ", textColor = {64, 64, 64}),
        Text(extent = {{-150, -110}, {150, -150}}, textString = "%name", textColor = {0, 0, 255})}));
  end SteerAxisIcon;

  partial model RevoluteIcon "Icon of a revolute joint (as Modelica.Mechanics.MultiBody.Joints.Revolute)"
    annotation(
      Icon(graphics = {
        Rectangle(extent = {{-100, -60}, {-30, 60}}, lineColor = {64, 64, 64}, fillColor = {192, 192, 192}, fillPattern = FillPattern.HorizontalCylinder, radius = 10),
        Rectangle(extent = {{30, -60}, {100, 60}}, lineColor = {64, 64, 64}, fillColor = {192, 192, 192}, fillPattern = FillPattern.HorizontalCylinder, radius = 10),
        Rectangle(extent = {{-30, 10}, {30, -10}}, lineColor = {64, 64, 64}, fillColor = {255, 255, 255}, fillPattern = FillPattern.Solid),
        Line(points = {{0, -90}, {0, 90}}, color = {0, 0, 0}, pattern = LinePattern.DashDot),
        Text(extent = {{-150, -110}, {150, -150}}, textString = "%name", textColor = {0, 0, 255})}));
  end RevoluteIcon;

  partial model Hinge "Icon of the rider's hip hinge: the upper body on a hinge above the seat"
    annotation(
      Icon(graphics = {
        Polygon(points = {{-13.6, -40}, {13.6, -40}, {18.6, 22}, {-18.6, 22}}, lineColor = {0, 0, 160}, fillColor = {120, 120, 220}, fillPattern = FillPattern.Solid),
        Ellipse(extent = {{-12.4, 28.2}, {12.4, 53}}, lineColor = {0, 0, 160}, fillColor = {0, 0, 160}, fillPattern = FillPattern.Solid),
        Line(points = {{-18.6, 18.9}, {-29.8, -15.2}, {-24.8, -40}}, color = {0, 0, 160}, thickness = 1),
        Line(points = {{18.6, 18.9}, {29.8, -15.2}, {24.8, -40}}, color = {0, 0, 160}, thickness = 1),
        Rectangle(extent = {{-70, -100}, {70, -74}}, lineColor = {64, 64, 64}, fillColor = {64, 64, 64}, fillPattern = FillPattern.Backward),
        Line(points = {{0, -74}, {0, -52}}, color = {64, 64, 64}, thickness = 1),
        Ellipse(extent = {{-16, -56}, {16, -24}}, lineColor = {0, 0, 0}, fillColor = {255, 255, 255}, fillPattern = FillPattern.Solid, lineThickness = 0.5),
        Ellipse(extent = {{-4, -44}, {4, -36}}, lineColor = {0, 0, 0}, fillColor = {0, 0, 0}, fillPattern = FillPattern.Solid),
        Line(points = {{28, 8.5}, {19.2, 12.6}, {9.7, 15.1}, {0, 16}, {-9.7, 15.1}, {-19.2, 12.6}, {-28, 8.5}}, color = {0, 0, 0}, arrow = {Arrow.Filled, Arrow.Filled}, arrowSize = 5, smooth = Smooth.Bezier),
        Text(extent = {{100, 20}, {260, -20}}, textString = "%name", textColor = {0, 0, 255}, horizontalAlignment = TextAlignment.Left)}));
  end Hinge;

  partial model UpperBodyIcon "Icon of the rider's upper body: trunk, arms and head above the hip"
    annotation(
      Icon(graphics = {
        Polygon(points = {{-27.5, -100}, {27.5, -100}, {37.5, 25}, {-37.5, 25}}, lineColor = {0, 0, 160}, fillColor = {120, 120, 220}, fillPattern = FillPattern.Solid),
        Ellipse(extent = {{-25, 37.5}, {25, 87.5}}, lineColor = {0, 0, 160}, fillColor = {0, 0, 160}, fillPattern = FillPattern.Solid),
        Line(points = {{-37.5, 18.8}, {-60, -50}, {-50, -100}}, color = {0, 0, 160}, thickness = 1),
        Line(points = {{37.5, 18.8}, {60, -50}, {50, -100}}, color = {0, 0, 160}, thickness = 1),
        Text(extent = {{-150, 110}, {150, 150}}, textString = "%name", textColor = {0, 0, 255})}));
  end UpperBodyIcon;

  partial model RigidBodyIcon "Icon of a rigid body: the body with its centre of mass, fixed to frame_a"
    annotation(
      Icon(graphics = {
        Rectangle(extent = {{-100, 6}, {-40, -6}}, lineColor = {0, 0, 0}, fillColor = {0, 0, 0}, fillPattern = FillPattern.Solid),
        Rectangle(extent = {{-40, 60}, {100, -60}}, lineColor = {0, 24, 48}, fillColor = {0, 127, 255}, fillPattern = FillPattern.HorizontalCylinder, radius = 10),
        Ellipse(extent = {{4, -26}, {56, 26}}, lineColor = {0, 0, 0}, fillColor = {255, 255, 255}, fillPattern = FillPattern.Solid),
        Ellipse(extent = {{4, -26}, {56, 26}}, lineColor = {0, 0, 0}, fillColor = {0, 0, 0}, fillPattern = FillPattern.Solid, pattern = LinePattern.None, startAngle = 0, endAngle = 90),
        Ellipse(extent = {{4, -26}, {56, 26}}, lineColor = {0, 0, 0}, fillColor = {0, 0, 0}, fillPattern = FillPattern.Solid, pattern = LinePattern.None, startAngle = 180, endAngle = 270),
        Text(extent = {{-150, -70}, {150, -100}}, textString = "m=%m", textColor = {0, 0, 0}),
        Text(extent = {{-150, 110}, {150, 150}}, textString = "%name", textColor = {0, 0, 255})}));
  end RigidBodyIcon;

  partial model FixedTranslationIcon "Icon of a rigid translation: a bar from frame_a to frame_b"
    annotation(
      Icon(graphics = {
        Rectangle(extent = {{-100, 6}, {100, -6}}, lineColor = {0, 0, 0}, fillColor = {0, 0, 0}, fillPattern = FillPattern.Solid),
        Polygon(points = {{50, -22}, {80, -30}, {50, -38}}, lineColor = {0, 0, 0}, fillColor = {0, 0, 0}, fillPattern = FillPattern.Solid),
        Line(points = {{-70, -30}, {52, -30}}, color = {0, 0, 0}),
        Text(extent = {{-150, -42}, {150, -82}}, textString = "r", textColor = {0, 0, 0}),
        Text(extent = {{-150, 40}, {150, 80}}, textString = "%name", textColor = {0, 0, 255})}));
  end FixedTranslationIcon;
  annotation(
    Icon(graphics = {
      Rectangle(extent = {{-100, -100}, {100, 100}}, lineColor = {200, 200, 200}, fillColor = {248, 248, 248}, fillPattern = FillPattern.HorizontalCylinder, radius = 25),
      Rectangle(extent = {{-100, -100}, {100, 100}}, lineColor = {128, 128, 128}, radius = 25),
      Polygon(origin = {-8.17, -17}, points = {{-15.83, 20}, {-15.83, 30}, {14.17, 40}, {24.17, 20}, {4.17, -30}, {14.17, -30}, {24.17, -30}, {24.17, -40}, {-5.83, -50}, {-15.83, -30}, {4.17, 20}, {-5.83, 20}}, lineColor = {128, 128, 128}, fillColor = {128, 128, 128}, fillPattern = FillPattern.Solid, pattern = LinePattern.None, smooth = Smooth.Bezier),
      Ellipse(origin = {-0.5, 56.5}, extent = {{-12.5, -12.5}, {12.5, 12.5}}, lineColor = {128, 128, 128}, fillColor = {128, 128, 128}, fillPattern = FillPattern.Solid, pattern = LinePattern.None)}),
    Documentation(info = "<html>
<p>Partial classes with nothing but an <code>Icon</code> annotation, in the style of
<code>Modelica.Icons</code> and <code>Modelica.Blocks.Icons</code>: the library's packages, examples
and blocks extend them, and so do the components whose icon several classes share (wheels, frames,
joints, the rider's hinge and upper body, rigid bodies and translations, bicycles). Each icon shows
the instance name (<code>%name</code>) above the class's graphics, except where connectors take that
place (the wheel, the joints, the hinge: beside or below).</p>
</html>"));
end Icons;
