within Bicycle;
package Bicycles "Bicycles assembled from components, exported as FMUs"
end Bicycles;
