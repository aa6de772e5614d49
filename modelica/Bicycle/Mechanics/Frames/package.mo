within Bicycle.Mechanics;
package Frames "The frames of a bicycle: rear frame, steer axis, front frame (fork and handlebar)"
  extends Bicycle.Icons.Package;
  annotation(Documentation(info = "<html><p>Composite components in the coordinates of Meijaard et al.
(2007): positions are given relative to the rear contact point of the upright bicycle with zero
steer (x forward, z down), as in Meijaard's Table 1.</p></html>"));
end Frames;
